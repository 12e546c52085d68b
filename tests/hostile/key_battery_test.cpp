// The generated battery over files: every key of every table of a scene file, a look file and
// a batch manifest, with the values a hostile user or a typo writes there (0, -1, nan, inf,
// 1e308, 2^31, 2^63, an empty string, a word, a boolean, arrays of such).  The keys are read
// from foldcast itself (the list an unknown key is answered with), so a new key is covered
// without editing this file; a new table needs a line below.  Each run is the real foldcast
// under a CPU and memory cap; it must exit 0 or 2 and never by a signal, print no library
// text, and when it refuses: a first line of ours naming the file and the key (or the key's
// line, for TOML the parser rejects), no number of more than 24 digits it was not given, and
// no file written.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <fstream>
#include <iostream>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "battery.hpp"
#include "spawn.hpp"
#include "test_paths.hpp"

namespace foldcast {
namespace {
namespace fs = std::filesystem;

const std::vector<std::string> kValues = {"0",
                                          "-1",
                                          "nan",
                                          "inf",
                                          "1e308",
                                          "2147483648",
                                          "9223372036854775808",
                                          "\"\"",
                                          "\"abc\"",
                                          "true",
                                          "[]",
                                          "[nan, nan, nan]",
                                          "[1e308, 1e308]",
                                          "[-1, -1, -1]",
                                          "[2147483648, 2147483648]"};
// 20 CPU seconds and 4 GiB: each base run below takes well under a second.
constexpr test::Limits kCap{20, 4ull << 30};

// One table of a TOML file: its header ("" at the top, "[garment]", "[[garments]]") and keys.
struct Table {
    std::string header;
    std::vector<std::pair<std::string, std::string>> keys;  // key, value as TOML text
    // The dotted name, as foldcast's messages write it ("garment", "lights.area").
    std::string name() const {
        std::string n = header;
        while (!n.empty() && (n.front() == '[')) n.erase(0, 1);
        while (!n.empty() && (n.back() == ']')) n.pop_back();
        return n;
    }
};

// A file of tables; `with` gives a copy where one key has another value.
struct TomlFile {
    std::string name;  // relative to the case's folder
    std::vector<Table> tables;

    // `key` of table `t` set to `value`; a top-level key naming a table replaces that table.
    TomlFile with(std::size_t t, const std::string& key, const std::string& value) const {
        TomlFile copy = *this;
        Table& table = copy.tables[t];
        bool found = false;
        for (auto& [k, v] : table.keys)
            if (k == key) {
                v = value;
                found = true;
            }
        if (!found) table.keys.emplace_back(key, value);
        if (table.header.empty())
            std::erase_if(copy.tables, [&](const Table& other) {
                const std::string n = other.name();
                return !other.header.empty() && (n == key || n.rfind(key + ".", 0) == 0);
            });
        return copy;
    }
    // The text, and the line (1-based) where `key` of the table named `table` is written.
    std::string text(const std::string& table = {}, const std::string& key = {}, int* line = nullptr) const {
        std::string out;
        int at = 1;
        for (const Table& t : tables) {
            if (!t.header.empty()) {
                out += t.header + "\n";
                ++at;
            }
            for (const auto& [k, v] : t.keys) {
                if (line && t.name() == table && k == key) *line = at;
                out += k + " = " + v + "\n";
                ++at;
            }
        }
        return out;
    }
};

// What one kind of file is tried with: the files of a run that succeeds, the one whose keys
// are tried, and the command.
struct Subject {
    std::string kind;
    std::vector<TomlFile> files;    // files[0] is the one tried
    std::vector<std::string> args;  // after the binary; FILE:name is the path of that file in the case folder
    std::string looks_dir;          // FOLDCAST_LOOKS_DIR (relative), or ""
};

struct Case {
    const Subject* subject;
    std::size_t table;
    std::string key, value;
};

void write(const fs::path& path, const std::string& bytes) {
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << bytes;
}

std::set<std::string> files_under(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir)) names.insert(fs::relative(e.path(), dir).string());
    return names;
}

// Writes the subject's files into `dir` (the tried file as `tried`) and runs its command.
test::Outcome run_subject(const Subject& s, const TomlFile& tried, const fs::path& dir) {
    fs::create_directories(dir);
    write(dir / tried.name, tried.text());
    for (std::size_t i = 1; i < s.files.size(); ++i) write(dir / s.files[i].name, s.files[i].text());
    std::vector<std::string> argv;
    if (!s.looks_dir.empty()) argv = {"/usr/bin/env", "FOLDCAST_LOOKS_DIR=" + (dir / s.looks_dir).string()};
    argv.push_back(test::foldcast_under_test());
    for (const std::string& a : s.args) argv.push_back(a.rfind("FILE:", 0) == 0 ? (dir / a.substr(5)).string() : a);
    return test::run_child(argv, dir.parent_path() / (dir.filename().string() + ".stderr"), kCap);
}

// The keys foldcast allows in table `t` of the subject's tried file: the list that an
// unknown key there is answered with.
std::vector<std::string> allowed_keys(const Subject& s, std::size_t t, const fs::path& dir) {
    const test::Outcome o = run_subject(s, s.files[0].with(t, "zz_probe", "1"), dir);
    const std::regex list(R"(unknown key '[^']*zz_probe'; allowed (?:at the top level|in \[.*\]): ([^\n]*))");
    std::smatch m;
    if (!std::regex_search(o.err, m, list)) {
        ADD_FAILURE() << s.kind << " table '" << s.files[0].tables[t].header << "': no list of keys in: " << o.err;
        return {};
    }
    std::vector<std::string> keys;
    std::istringstream items(m[1].str());
    for (std::string k; std::getline(items, k, ',');) {
        k.erase(0, k.find_first_not_of(' '));
        if (!k.empty() && k != "none") keys.push_back(k);
    }
    fs::remove_all(dir);
    return keys;
}

// Runs one case in a folder of its own; returns what is wrong with the outcome ("" if nothing).
std::string check(const Case& c, const fs::path& dir, std::atomic<std::size_t>& accepted) {
    const Subject& s = *c.subject;
    const TomlFile tried = s.files[0].with(c.table, c.key, c.value);
    const std::string table = s.files[0].tables[c.table].name();
    int line = 0;
    tried.text(table, c.key, &line);
    // What the inputs are, to tell a written output from them.
    fs::create_directories(dir);
    const std::string what = s.kind + " " + (table.empty() ? "" : "[" + table + "] ") + c.key + " = " + c.value;
    const test::Outcome o = run_subject(s, tried, dir);
    if (!o.exited) return what + ": killed by signal " + std::to_string(o.signal) + ": " + o.err;
    if (o.exit_code != 0 && o.exit_code != 2) return what + ": exit " + std::to_string(o.exit_code) + ": " + o.err;
    for (const char* noise : {"[ WARN", "[ERROR", "TBB Warning", "terminate called", "filesystem error", "[mpeg4",
                              "std::bad_alloc", "what():", "Assertion"})
        if (o.err.find(noise) != std::string::npos) return what + ": library text on stderr: " + o.err;
    if (o.exit_code == 0) {
        ++accepted;
        return {};
    }
    const std::string first = o.err.substr(0, o.err.find('\n'));
    if (first.rfind("foldcast:", 0) != 0) return what + ": the first line is not ours: " + o.err;
    const std::string file = fs::path(tried.name).filename().string();
    const bool names_key = first.find(c.key) != std::string::npos;
    const bool names_line = first.find(file + ":" + std::to_string(line) + ":") != std::string::npos;
    if (first.find(file) == std::string::npos || !(names_key || names_line))
        return what + ": the first line does not name " + file + " and " + c.key + ": " + first;
    if (test::longest_digit_run(first) > std::max<std::size_t>(24, test::longest_digit_run(c.value)))
        return what + ": the first line prints a number of " + std::to_string(test::longest_digit_run(first)) +
               " digits: " + first;
    std::set<std::string> inputs = {tried.name};
    for (const TomlFile& f : s.files)
        for (fs::path p = f.name; !p.empty(); p = p.parent_path()) inputs.insert(p.string());
    for (const std::string& name : files_under(dir))
        if (!inputs.count(name)) return what + ": refused, yet " + name + " was written: " + first;
    return {};
}

class KeyBattery : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = test::temp_dir();
        const TomlFile tiny{
            "tiny.toml",
            {{"[garment]", {{"grid", "[9, 9]"}}}, {"[output]", {{"width", "16"}, {"height", "16"}, {"spp", "1"}}}}};
        // Every table a scene may hold, each present (empty where its defaults do).
        const TomlFile scene{"scene.toml",
                             {{"", {}},
                              {"[garment]", {{"grid", "[9, 9]"}}},
                              {"[camera]", {}},
                              {"[lights]", {}},
                              {"[[lights.area]]", {}},
                              {"[backdrop]", {}},
                              {"[supports]", {}},
                              {"[output]", {{"width", "16"}, {"height", "16"}, {"spp", "1"}}},
                              {"[turntable]", {}}}};
        subjects_.push_back({"scene", {scene}, {"render", "FILE:scene.toml", "-o", "FILE:out.png", "--quiet"}, ""});
        const TomlFile look{
            "looks/linen.toml",
            {{"", {{"description", "\"a look\""}}},
             {"[mechanics]", {{"thickness_mm", "0.35"}, {"gsm", "170"}, {"young_mpa", "5.0"}, {"poisson", "0.3"}}},
             {"[appearance]", {{"base_colour", "\"#cbbd9f\""}, {"weave", "\"plain\""}}}}};
        subjects_.push_back(
            {"look", {look, tiny}, {"render", "FILE:tiny.toml", "-o", "FILE:out.png", "--quiet"}, "looks"});
        const TomlFile manifest{
            "batch.toml",
            {{"",
              {{"output_dir", "\"cat\""}, {"width", "16"}, {"height", "16"}, {"spp", "1"}, {"looks", "[\"linen\"]"}}},
             {"[[garments]]", {{"name", "\"a\""}, {"scene", "\"tiny.toml\""}}},
             {"[[views]]", {{"name", "\"front\""}}}}};
        subjects_.push_back({"manifest", {manifest, tiny}, {"batch", "FILE:batch.toml", "--quiet"}, ""});
    }
    fs::path dir_;
    std::vector<Subject> subjects_;
};

TEST_F(KeyBattery, EveryKeyOfEveryFileTakesHostileValues) {
    std::vector<Case> cases;
    for (const Subject& s : subjects_) {
        const test::Outcome base = run_subject(s, s.files[0], dir_ / ("base_" + s.kind));
        ASSERT_TRUE(base.exited && base.exit_code == 0) << s.kind << "'s base run fails: " << base.err;
        for (std::size_t t = 0; t < s.files[0].tables.size(); ++t) {
            const std::vector<std::string> keys = allowed_keys(s, t, dir_ / ("probe_" + s.kind));
            EXPECT_FALSE(keys.empty()) << s.kind << " table '" << s.files[0].tables[t].header << "' lists no keys";
            for (const std::string& key : keys)
                for (const std::string& value : kValues) cases.push_back({&s, t, key, value});
        }
    }
    std::atomic<std::size_t> accepted{0};
    const std::vector<std::string> failures = test::run_on_two_threads(cases.size(), [&](std::size_t i) {
        const fs::path dir = dir_ / ("case" + std::to_string(i));
        const std::string wrong = check(cases[i], dir, accepted);
        fs::remove_all(dir);
        fs::remove(dir_ / ("case" + std::to_string(i) + ".stderr"));
        return wrong;
    });
    std::cout << cases.size() << " cases (" << accepted << " accepted, the rest refused), " << failures.size()
              << " failed\n";
    for (const std::string& f : failures) ADD_FAILURE() << f;
}

}  // namespace
}  // namespace foldcast
