// The table of look keys drives parsing, output and the docs: each must agree with it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <toml++/toml.h>

#include "foldcast/looks/looks.hpp"
#include "foldcast/looks/look_json.hpp"
#include "foldcast/looks/look_keys.hpp"
#include "shipped_looks.hpp"

namespace foldcast::looks {
namespace {

TEST(LookKeys, DocsHoldTheTablesTheCodeReads) {
    std::ifstream in(std::filesystem::path(FOLDCAST_SOURCE_DIR) / "docs/looks.md");
    std::stringstream doc;
    doc << in.rdbuf();
    EXPECT_NE(doc.str().find(look_keys_markdown()), std::string::npos)
        << "docs/looks.md is out of date: paste the output of `foldcast looks keys`:\n"
        << look_keys_markdown();
}

TEST(LookKeys, EveryWrittenKeyAppearsInTomlAndJsonAndReadsBack) {
    const Look& denim = test::shipped_looks().get("denim");
    const std::string text = format_look_toml(denim);
    const toml::table table = toml::parse(text);
    const nlohmann::json json = denim;
    for (const LookKey& key : look_keys()) {
        const std::string section = section_name(key.section);
        const bool set = !std::holds_alternative<std::monostate>(key.get(denim));
        EXPECT_EQ(table[section].as_table()->contains(key.name), key.written && set) << key.name;
        if (key.written) {
            EXPECT_TRUE(json[section].contains(std::string(key.name))) << key.name;
        }
    }
    const Look back = parse_look(table, "denim", "printed.toml");
    for (const LookKey& key : look_keys()) {
        const LookValue a = key.get(denim), b = key.get(back);
        if (const auto* x = std::get_if<double>(&a)) {
            EXPECT_NEAR(*x, std::get<double>(b), 1e-5 * std::abs(*x)) << key.name;
        } else {
            EXPECT_EQ(a.index(), b.index()) << key.name;
        }
    }
}

}  // namespace
}  // namespace foldcast::looks
