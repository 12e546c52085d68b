#include "source_scan.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <regex>
#include <sstream>

namespace foldcast::repo_scan {

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

namespace {

// The source with comments, string and character literals and preprocessor lines blanked
// (newlines kept, so line numbers stay), leaving only code that braces can be counted in.
std::string code_only(const std::string& s) {
    std::string out = s;
    const std::size_t n = s.size();
    std::size_t i = 0;
    bool line_start = true;
    auto blank = [&](std::size_t from, std::size_t to) {
        for (std::size_t k = from; k < to && k < n; ++k) {
            if (out[k] != '\n') out[k] = ' ';
        }
    };
    while (i < n) {
        const char c = s[i];
        if (c == '\n') {
            line_start = true;
            ++i;
            continue;
        }
        if (line_start && c == '#') {  // a directive, with its continuation lines
            std::size_t j = i;
            while (j < n && !(s[j] == '\n' && s[j - 1] != '\\')) ++j;
            blank(i, j);
            i = j;
            continue;
        }
        if (!std::isspace(static_cast<unsigned char>(c))) line_start = false;
        if (c == '/' && i + 1 < n && s[i + 1] == '/') {
            std::size_t j = s.find('\n', i);
            if (j == std::string::npos) j = n;
            blank(i, j);
            i = j;
        } else if (c == '/' && i + 1 < n && s[i + 1] == '*') {
            std::size_t j = s.find("*/", i + 2);
            j = j == std::string::npos ? n : j + 2;
            blank(i, j);
            i = j;
        } else if (c == 'R' && i + 1 < n && s[i + 1] == '"' &&
                   (i == 0 || !(std::isalnum(static_cast<unsigned char>(s[i - 1])) || s[i - 1] == '_'))) {
            const std::size_t open = s.find('(', i + 2);
            const std::string close = ")" + s.substr(i + 2, open - (i + 2)) + "\"";
            std::size_t j = s.find(close, open);
            j = j == std::string::npos ? n : j + close.size();
            blank(i, j);
            i = j;
        } else if (c == '"' || (c == '\'' && (i == 0 || !std::isxdigit(static_cast<unsigned char>(s[i - 1]))))) {
            std::size_t j = i + 1;
            while (j < n && s[j] != c && s[j] != '\n') j += s[j] == '\\' ? 2 : 1;
            blank(i, j + 1);
            i = j + 1;
        } else {
            ++i;
        }
    }
    return out;
}

enum class Scope { Namespace, Class, Function, Other };

bool is_word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// Whether `text` holds `word` as a whole word (no regex: this runs at every brace).
bool has_word(const std::string& text, const std::string& word) {
    for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) {
        const bool start = at == 0 || !is_word_char(text[at - 1]);
        const bool end = at + word.size() >= text.size() || !is_word_char(text[at + word.size()]);
        if (start && end) return true;
    }
    return false;
}

// What a `{` opens, from the code between the previous `;`, `{` or `}` and it.
Scope classify(const std::string& head) {
    const std::size_t last_paren = head.rfind(')');
    const std::string after = last_paren == std::string::npos ? head : head.substr(last_paren);
    if (last_paren == std::string::npos && (has_word(head, "namespace") || has_word(head, "extern")))
        return Scope::Namespace;
    if (has_word(after, "class") || has_word(after, "struct") || has_word(after, "union") || has_word(after, "enum"))
        return Scope::Class;
    if (last_paren == std::string::npos) return Scope::Other;
    // An initialiser (`x = f(...) {` cannot be a body); `operator=` and comparisons are no `=`.
    const std::size_t first_paren = head.find('(');
    const std::string before = head.substr(0, first_paren);
    for (std::size_t k = 0; k < before.size(); ++k) {
        if (before[k] != '=') continue;
        const char prev = k > 0 ? before[k - 1] : ' ';
        const char next = k + 1 < before.size() ? before[k + 1] : ' ';
        if (prev == '=' || next == '=' || prev == '!' || prev == '<' || prev == '>') continue;
        if (before.find("operator") != std::string::npos) continue;
        return Scope::Other;
    }
    return Scope::Function;
}

// `{` inside a constructor's member initialisers (`: a_{x}, b_(y) {`) opens no scope.
bool member_initialiser_brace(const std::string& head) {
    const std::size_t last_paren = head.rfind(')');
    if (last_paren == std::string::npos) return false;
    std::size_t colon = std::string::npos;
    for (std::size_t k = last_paren; k < head.size(); ++k) {
        if (head[k] == ':' && (k + 1 >= head.size() || head[k + 1] != ':') && (k == 0 || head[k - 1] != ':')) colon = k;
    }
    if (colon == std::string::npos && head.find(") :") == std::string::npos && head.find("):") == std::string::npos)
        return false;
    std::size_t k = head.find_last_not_of(" \t\n");
    if (k == std::string::npos) return false;
    const char c = head[k];
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '>';
}

// `public`, `private` or `protected` at the end of `head` (before a colon).
bool ends_with_access_label(const std::string& head) {
    std::size_t end = head.find_last_not_of(" \t\n");
    if (end == std::string::npos) return false;
    std::size_t start = end + 1;
    while (start > 0 && is_word_char(head[start - 1])) --start;
    const std::string word = head.substr(start, end + 1 - start);
    return word == "public" || word == "private" || word == "protected";
}

std::string function_name(const std::string& head) {
    static const std::regex name(R"(((?:[A-Za-z_~][\w:~]*|operator\s*\S+?))\s*\()");
    std::smatch m;
    if (std::regex_search(head, m, name)) return m[1].str();
    return "?";
}

}  // namespace

std::vector<FunctionSpan> function_spans(const std::string& source, const std::string& file) {
    const std::string code = code_only(source);
    std::vector<FunctionSpan> spans;
    std::vector<Scope> stack;
    std::vector<FunctionSpan> open;  // the function bodies being read, innermost last
    std::string head;
    std::size_t head_start = std::string::npos;
    int line = 1;
    int init_depth = 0;  // braces inside a member initialiser list
    auto in_body = [&] {
        return std::any_of(stack.begin(), stack.end(),
                           [](Scope s) { return s == Scope::Function || s == Scope::Other; });
    };
    std::vector<int> line_of(code.size() + 1, 1);
    for (std::size_t i = 0; i < code.size(); ++i) {
        line_of[i] = line;
        if (code[i] == '\n') ++line;
    }
    for (std::size_t i = 0; i < code.size(); ++i) {
        const char c = code[i];
        if (in_body()) {
            if (c == '{') stack.push_back(Scope::Other);
            if (c == '}') {
                const Scope closed = stack.back();
                stack.pop_back();
                if (closed == Scope::Function) {
                    FunctionSpan span = open.back();
                    open.pop_back();
                    span.lines = line_of[i] - span.first_line + 1;
                    spans.push_back(span);
                }
            }
            if (!in_body()) {
                head.clear();
                head_start = std::string::npos;
            }
            continue;
        }
        if (init_depth > 0) {
            head += c;
            if (c == '{') ++init_depth;
            if (c == '}') --init_depth;
            continue;
        }
        if (c == '{') {
            if (member_initialiser_brace(head)) {
                head += c;
                init_depth = 1;
                continue;
            }
            const Scope scope = classify(head);
            if (scope == Scope::Function) {
                FunctionSpan span;
                span.file = file;
                span.name = function_name(head);
                span.first_line = head_start == std::string::npos ? line_of[i] : line_of[head_start];
                open.push_back(span);
            }
            stack.push_back(scope);
            head.clear();
            head_start = std::string::npos;
        } else if (c == '}' || c == ';') {
            if (c == '}' && !stack.empty()) stack.pop_back();
            head.clear();
            head_start = std::string::npos;
        } else {
            if (head_start == std::string::npos && !std::isspace(static_cast<unsigned char>(c))) head_start = i;
            if (c == ':' && ends_with_access_label(head)) {
                head.clear();
                head_start = std::string::npos;
                continue;
            }
            head += c;
        }
    }
    return spans;
}

std::vector<std::filesystem::path> cpp_files(const std::filesystem::path& repo, const std::vector<std::string>& roots) {
    std::vector<std::filesystem::path> files;
    for (const auto& root : roots) {
        if (!std::filesystem::exists(repo / root)) continue;
        for (auto it = std::filesystem::recursive_directory_iterator(repo / root);
             it != std::filesystem::recursive_directory_iterator(); ++it) {
            if (it->is_directory() && it->path().filename() == "node_modules") {  // npm's, not ours
                it.disable_recursion_pending();
                continue;
            }
            const auto ext = it->path().extension();
            if (it->is_regular_file() && (ext == ".cpp" || ext == ".hpp")) files.push_back(it->path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace foldcast::repo_scan
