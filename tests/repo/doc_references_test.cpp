// Every reference from code to a section of a doc (`docs/render.md, "Denoiser"` or
// `docs/render.md ("Denoiser")`, also wrapped over comment lines) names a doc that exists and a
// section in it: a heading, or a paragraph's bold lead-in (`**Thread smoothing: ...**`), that
// starts with the quoted words.
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <sstream>

#include "source_scan.hpp"

namespace doc_references_test {

using namespace foldcast::repo_scan;
namespace fs = std::filesystem;

// The section titles of a Markdown doc: headings and bold lead-ins, without their markup.
std::vector<std::string> section_titles(const std::string& markdown) {
    std::vector<std::string> titles;
    std::istringstream lines(markdown);
    std::string line;
    static const std::regex heading(R"(^#{1,6}\s+(.*\S)\s*$)");
    static const std::regex lead_in(R"(^(?:[-*]\s+)?\*\*([^*]+)\*\*)");
    std::smatch m;
    while (std::getline(lines, line)) {
        if (std::regex_search(line, m, heading) || std::regex_search(line, m, lead_in)) titles.push_back(m[1].str());
    }
    return titles;
}

// "Relaxation" names "Relaxation: garments that keep their length"; "A ..." any title starting "A".
bool names_section(const std::string& reference, const std::vector<std::string>& titles) {
    std::string words = reference;
    const bool prefix = words.size() > 4 && words.compare(words.size() - 4, 4, " ...") == 0;
    if (prefix) words.resize(words.size() - 4);
    words = std::regex_replace(words, std::regex(R"(^#+\s*)"), "");
    for (const auto& title : titles) {
        if (title == words) return true;
        if (title.rfind(words, 0) != 0) continue;
        const char next = title[words.size()];
        if (prefix || next == ':' || next == ' ' || next == ',' || next == '.') return true;
    }
    return false;
}

struct Reference {
    std::string file, doc, section;
};

// References in one file's text; comment markers at the start of continued lines are dropped
// so that a reference wrapped over two comment lines reads as one.
std::vector<Reference> references(const std::string& text, const std::string& file) {
    const std::string joined = std::regex_replace(text, std::regex(R"(\n\s*(//|#|\*)?\s*)"), " ");
    static const std::regex reference(
        R"re(docs/([a-z0-9_-]+\.md)(?:,\s*|\s*\(\s*)((?:\\?"[^"\\]+\\?"(?:,\s*|\s+and\s+)?)+))re");
    static const std::regex quoted(R"re(\\?"([^"\\]+)\\?")re");
    std::vector<Reference> found;
    for (auto it = std::sregex_iterator(joined.begin(), joined.end(), reference); it != std::sregex_iterator(); ++it) {
        const std::string names = (*it)[2].str();
        for (auto q = std::sregex_iterator(names.begin(), names.end(), quoted); q != std::sregex_iterator(); ++q)
            found.push_back({file, (*it)[1].str(), (*q)[1].str()});
    }
    return found;
}

std::vector<fs::path> referring_files() {
    std::vector<fs::path> files =
        cpp_files(FOLDCAST_SOURCE_DIR, {"core", "looks", "drape", "codec", "serve", "render", "preview", "batch",
                                        "compare", "export", "app", "bench", "web/wasm", "tests", "cmake"});
    // This test's own examples are not references.
    std::erase_if(files, [](const fs::path& f) { return f.parent_path().filename() == "repo"; });
    const fs::path root(FOLDCAST_SOURCE_DIR);
    for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
        const std::string name = it->path().filename().string();
        // Build trees, git's store, npm's packages and shared data are not the project's text.
        if (it->is_directory() && (name.rfind("build", 0) == 0 || name == ".git" || name == "node_modules" ||
                                   (name == "shared" && it->path().parent_path() == root))) {
            it.disable_recursion_pending();
            continue;
        }
        const std::string ext = it->path().extension().string();
        if (it->is_regular_file() && (name == "CMakeLists.txt" || ext == ".cmake" || ext == ".sh" || ext == ".md" ||
                                      ext == ".mjs" || ext == ".py" || ext == ".toml"))
            files.push_back(it->path());
    }
    return files;
}

TEST(DocReferences, EverySectionNamedInCodeExists) {
    std::ostringstream broken;
    int checked = 0;
    for (const auto& file : referring_files()) {
        const std::string relative = fs::relative(file, FOLDCAST_SOURCE_DIR).string();
        const std::string text = read_text(file);
        if (text.find("docs/") == std::string::npos) continue;  // most files cite no doc
        for (const Reference& ref : references(text, relative)) {
            ++checked;
            const fs::path doc = fs::path(FOLDCAST_SOURCE_DIR) / "docs" / ref.doc;
            if (!fs::exists(doc)) {
                broken << "  " << ref.file << ": docs/" << ref.doc << " does not exist\n";
                continue;
            }
            if (!names_section(ref.section, section_titles(read_text(doc))))
                broken << "  " << ref.file << ": docs/" << ref.doc << " has no section \"" << ref.section << "\"\n";
        }
    }
    EXPECT_GT(checked, 20) << "too few references found to be reading the sources";
    EXPECT_TRUE(broken.str().empty()) << "references to missing docs or sections:\n" << broken.str();
}

TEST(DocReferences, ReadsWrappedAndParenthesisedReferences) {
    const auto refs =
        references("// see docs/render.md (\"Denoiser\", \"Mixed\n// pixels\") and docs/drape.md, \"A\"", "x.cpp");
    ASSERT_EQ(refs.size(), 3u);
    EXPECT_EQ(refs[0].section, "Denoiser");
    EXPECT_EQ(refs[1].section, "Mixed pixels");
    EXPECT_EQ(refs[2].doc, "drape.md");
    const std::vector<std::string> titles = section_titles("# T\n## Relaxation: keep length\n**Lead in.** text\n");
    EXPECT_TRUE(names_section("Relaxation", titles));
    EXPECT_TRUE(names_section("Lead in.", titles));
    EXPECT_FALSE(names_section("Relax", titles));
    EXPECT_FALSE(names_section("Denoiser", titles));
}

}  // namespace doc_references_test
