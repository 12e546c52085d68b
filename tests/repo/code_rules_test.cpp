// Rules of foldcast's own code (docs/architecture.md, "Code"): no function runs over
// kMaxFunctionLines lines (longer ones are split into named steps; the scanner counts from a
// function's signature to its closing brace, lambdas with the function that holds them), and
// pi is core's kPi, not the POSIX M_PI macro.
#include <gtest/gtest.h>

#include <sstream>

#include "source_scan.hpp"

namespace code_rules_test {

using namespace foldcast::repo_scan;

constexpr int kMaxFunctionLines = 120;

const std::vector<std::string> kCodeRoots{"core",  "looks",   "drape",  "codec", "serve", "render",   "preview",
                                          "batch", "compare", "export", "app",   "bench", "web/wasm", "tests"};

TEST(CodeRules, NoFunctionIsLongerThanTheLimit) {
    const std::vector<std::string>& roots = kCodeRoots;
    std::ostringstream long_ones;
    int scanned = 0;
    for (const auto& file : cpp_files(FOLDCAST_SOURCE_DIR, roots)) {
        const std::string relative = std::filesystem::relative(file, FOLDCAST_SOURCE_DIR).string();
        for (const FunctionSpan& span : function_spans(read_text(file), relative)) {
            ++scanned;
            if (span.lines > kMaxFunctionLines)
                long_ones << "  " << span.file << ":" << span.first_line << " " << span.name << ": " << span.lines
                          << " lines\n";
        }
    }
    EXPECT_GT(scanned, 1000) << "the scanner found too few functions to be reading the sources";
    EXPECT_TRUE(long_ones.str().empty()) << "functions over " << kMaxFunctionLines
                                         << " lines (split them into named steps):\n"
                                         << long_ones.str();
}

// The scanner itself, on a source that has what foldcast's code has: classes, namespaces,
// constructors with member initialisers, lambdas, braces in strings and comments.
TEST(CodeRules, ScannerCountsSignatureToClosingBrace) {
    const std::string source =
        "#include <x>\n"                                    // 1
        "namespace a {\n"                                   // 2
        "struct S {\n"                                      // 3
        "    S(int v) : v_{v}, w_(v) {}\n"                  // 4
        "    int f() const {\n"                             // 5
        "        return v_; // }\n"                         // 6
        "    }\n"                                           // 7
        "    int v_, w_;\n"                                 // 8
        "};\n"                                              // 9
        "const int kTable[] = {1, 2};\n"                    // 10
        "int g(int x)\n"                                    // 11
        "{\n"                                               // 12
        "    auto l = [&](int y) { return \"{\" + y; };\n"  // 13
        "    if (x) { x = l(x); }\n"                        // 14
        "    return x;\n"                                   // 15
        "}\n"                                               // 16
        "}  // namespace a\n";                              // 17
    const auto spans = function_spans(source, "x.cpp");
    ASSERT_EQ(spans.size(), 3u);
    EXPECT_EQ(spans[0].name, "S");
    EXPECT_EQ(spans[0].lines, 1);
    EXPECT_EQ(spans[1].name, "f");
    EXPECT_EQ(spans[1].first_line, 5);
    EXPECT_EQ(spans[1].lines, 3);
    EXPECT_EQ(spans[2].name, "g");
    EXPECT_EQ(spans[2].first_line, 11);
    EXPECT_EQ(spans[2].lines, 6);
}

TEST(CodeRules, PiIsCoresConstant) {
    std::ostringstream uses;
    for (const auto& file : cpp_files(FOLDCAST_SOURCE_DIR, kCodeRoots)) {
        const std::string relative = std::filesystem::relative(file, FOLDCAST_SOURCE_DIR).string();
        if (relative == "tests/repo/code_rules_test.cpp") continue;
        if (read_text(file).find(std::string("M_") + "PI") != std::string::npos) uses << "  " << relative << "\n";
    }
    EXPECT_TRUE(uses.str().empty()) << "M_PI (POSIX, not C++) where core/math.hpp's kPi is meant:\n" << uses.str();
}

}  // namespace code_rules_test
