// Finding and loading look files.
#include <toml++/toml.h>

#include <cstdlib>
#include <string>

#include "foldcast/core/error.hpp"
#include "foldcast/looks/looks.hpp"

#ifndef FOLDCAST_LOOKS_DATA_DIR
#error "FOLDCAST_LOOKS_DATA_DIR must name the shipped looks/data folder (looks/CMakeLists.txt)"
#endif

namespace foldcast::looks {
namespace fs = std::filesystem;

Look load_look_file(const fs::path& file) {
    toml::table table;
    try {
        table = toml::parse_file(file.string());
    } catch (const toml::parse_error& error) {
        const auto& where = error.source().begin;
        std::error_code ignored;
        if (!fs::exists(file, ignored)) throw InputError("look file '" + file.string() + "' does not exist");
        throw InputError(file.string() + ":" + std::to_string(where.line) + ":" + std::to_string(where.column) +
                         ": not valid TOML: " + std::string(error.description()));
    }
    return parse_look(table, file.stem().string(), file.string());
}

Library Library::load_directory(const fs::path& dir) {
    std::error_code error;
    if (!fs::is_directory(dir, error))
        throw InputError("looks directory '" + dir.string() +
                         "' does not exist (set FOLDCAST_LOOKS_DIR to a folder of *.toml looks)");
    Library library;
    library.directory_ = dir;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (!entry.is_regular_file() || entry.path().extension() != ".toml") continue;
        Look look = load_look_file(entry.path());
        library.looks_.emplace(look.name, std::move(look));
    }
    if (library.looks_.empty()) throw InputError("looks directory '" + dir.string() + "' holds no *.toml look files");
    return library;
}

Library Library::load_default() {
    if (const char* dir = std::getenv("FOLDCAST_LOOKS_DIR"); dir && *dir) return load_directory(dir);
    return load_directory(FOLDCAST_LOOKS_DATA_DIR);
}

std::vector<std::string> Library::names() const {
    std::vector<std::string> names;
    names.reserve(looks_.size());
    for (const auto& [name, look] : looks_) names.push_back(name);
    return names;  // std::map keeps them sorted
}

bool Library::contains(const std::string& name) const { return looks_.count(name) != 0; }

Look Library::find(const std::string& name_or_file, const fs::path& base_dir) const {
    const bool is_file = name_or_file.find('/') != std::string::npos || fs::path(name_or_file).extension() == ".toml";
    if (!is_file) return get(name_or_file);
    fs::path file(name_or_file);
    if (file.is_relative() && !base_dir.empty()) file = base_dir / file;
    std::error_code error;
    if (!fs::is_regular_file(file, error))
        throw InputError("look file '" + file.string() +
                         "' does not exist (a look is a name from `foldcast looks` "
                         "or the path of a look .toml file)");
    return load_look_file(file);
}

const Look& Library::get(const std::string& name) const {
    if (auto it = looks_.find(name); it != looks_.end()) return it->second;
    std::string available;
    for (const auto& [known, look] : looks_) {
        if (!available.empty()) available += ", ";
        available += known;
    }
    throw InputError("unknown look '" + name + "'; available looks: " + available);
}

}  // namespace foldcast::looks
