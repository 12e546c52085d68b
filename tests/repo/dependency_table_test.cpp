// docs/architecture.md's table of what each room may depend on, held to the CMake files and
// the #include lines: each room's foldcast_module() lists (app's target_link_libraries) name
// the rooms and third-party libraries the table gives it, and each room includes headers only
// of itself, the rooms it links and the third-party libraries it links or gets through a room's
// public dependencies.  Every public header sits at <room>/include/foldcast/<room>/NAME.hpp.
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "source_scan.hpp"

namespace dependency_table_test {

using namespace foldcast::repo_scan;
namespace fs = std::filesystem;
using Names = std::set<std::string>;

const Names kRooms{"core",    "looks", "drape",   "codec",  "serve", "render",
                   "preview", "batch", "compare", "export", "app"};

// CMake target -> the name docs/architecture.md uses.
const std::map<std::string, std::string> kThirdPartyTargets{{"Eigen3::Eigen", "Eigen"},
                                                            {"tomlplusplus::tomlplusplus", "toml++"},
                                                            {"tinyobjloader::tinyobjloader", "tinyobjloader"},
                                                            {"nlohmann_json::nlohmann_json", "JSON"},
                                                            {"TBB::tbb", "TBB"},
                                                            {"PkgConfig::fftw3", "FFTW"},
                                                            {"zstd::libzstd_shared", "zstd"},
                                                            {"PkgConfig::libdeflate", "libdeflate"},
                                                            {"PkgConfig::httplib", "cpp-httplib"},
                                                            {"embree", "Embree"},
                                                            {"OpenEXR::OpenEXR", "OpenEXR"},
                                                            {"OpenGL::EGL", "EGL"},
                                                            {"OpenGL::OpenGL", "OpenGL"},
                                                            {"OpenSSL::Crypto", "OpenSSL"},
                                                            {"meshoptimizer::meshoptimizer", "meshoptimizer"},
                                                            {"CLI11::CLI11", "CLI11"}};

// An #include's first path component (or header) -> the library it belongs to.
const std::map<std::string, std::string> kThirdPartyHeaders{{"Eigen", "Eigen"},
                                                            {"toml++", "toml++"},
                                                            {"tiny_obj_loader.h", "tinyobjloader"},
                                                            {"nlohmann", "JSON"},
                                                            {"tbb", "TBB"},
                                                            {"fftw3.h", "FFTW"},
                                                            {"zstd.h", "zstd"},
                                                            {"libdeflate.h", "libdeflate"},
                                                            {"httplib.h", "cpp-httplib"},
                                                            {"embree3", "Embree"},
                                                            {"embree4", "Embree"},
                                                            {"OpenEXR", "OpenEXR"},
                                                            {"Imath", "OpenEXR"},
                                                            {"EGL", "EGL"},
                                                            {"GL", "OpenGL"},
                                                            {"openssl", "OpenSSL"},
                                                            {"meshoptimizer.h", "meshoptimizer"},
                                                            {"CLI", "CLI11"},
                                                            {"opencv2", "OpenCV"}};

struct Deps {
    Names public_rooms, private_rooms, public_libs, private_libs;
};

std::string library_name(const std::string& target) {
    if (target.rfind("opencv_", 0) == 0) return "OpenCV";
    const auto it = kThirdPartyTargets.find(target);
    return it == kThirdPartyTargets.end() ? "" : it->second;
}

void add_target(const std::string& target, Names& rooms, Names& libs, std::ostringstream& unknown) {
    if (target.rfind("foldcast::", 0) == 0) {
        rooms.insert(target.substr(10));
    } else if (target == "foldcast_options") {
    } else if (const std::string lib = library_name(target); !lib.empty()) {
        libs.insert(lib);
    } else {
        unknown << " " << target;
    }
}

std::vector<std::string> words(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> out;
    for (std::string w; in >> w;) out.push_back(w);
    return out;
}

// What a room's CMakeLists.txt links: foldcast_module's PUBLIC_DEPS and PRIVATE_DEPS, or for
// app its target_link_libraries (all private).
Deps cmake_deps(const std::string& room, std::ostringstream& unknown) {
    std::string text = read_text(fs::path(FOLDCAST_SOURCE_DIR) / room / "CMakeLists.txt");
    text = std::regex_replace(text, std::regex("#[^\n]*"), "");
    Deps deps;
    std::smatch m;
    if (room == "app") {
        if (std::regex_search(text, m, std::regex(R"(target_link_libraries\(foldcast\s+PRIVATE([^)]*)\))")))
            for (const auto& w : words(m[1].str())) add_target(w, deps.private_rooms, deps.private_libs, unknown);
        return deps;
    }
    if (!std::regex_search(text, m, std::regex(R"(foldcast_module\(\w+([^)]*)\))"))) return deps;
    Names* rooms = nullptr;
    Names* libs = nullptr;
    for (const auto& w : words(m[1].str())) {
        if (w == "SOURCES") {
            rooms = nullptr;
            libs = nullptr;
            continue;
        }
        if (w == "PUBLIC_DEPS") {
            rooms = &deps.public_rooms;
            libs = &deps.public_libs;
            continue;
        }
        if (w == "PRIVATE_DEPS") {
            rooms = &deps.private_rooms;
            libs = &deps.private_libs;
            continue;
        }
        if (rooms) add_target(w, *rooms, *libs, unknown);
    }
    return deps;
}

// One cell of the table: rooms outside parentheses, third-party libraries inside (their first
// word; "the `ffmpeg` program" is a program, not linked).
void parse_cell(const std::string& cell, Names& rooms, Names& libs) {
    std::string outside, inside;
    int depth = 0;
    for (char c : cell) {
        if (c == '(') {
            if (depth++ == 0) continue;
        }
        if (c == ')') {
            if (--depth == 0) continue;
        }
        (depth > 0 ? inside : outside) += c;
    }
    for (const auto& w : words(std::regex_replace(outside, std::regex("[,;]"), " "))) rooms.insert(w);
    std::istringstream items(std::regex_replace(inside, std::regex(";"), ","));
    for (std::string item; std::getline(items, item, ',');) {
        if (item.find("program") != std::string::npos) continue;
        const auto ws = words(item);
        if (ws.empty()) continue;
        std::string name = ws.front();
        while (!name.empty() && (name.back() == ':' || name.back() == '.')) name.pop_back();
        libs.insert(name);
    }
}

std::map<std::string, Deps> documented_deps() {
    const std::string doc = read_text(fs::path(FOLDCAST_SOURCE_DIR) / "docs" / "architecture.md");
    std::map<std::string, Deps> table;
    std::istringstream lines(doc);
    static const std::regex row(R"(^\|\s*([a-z]+)\s*\|([^|]*)\|([^|]*)\|\s*$)");
    std::smatch m;
    for (std::string line; std::getline(lines, line);) {
        if (!std::regex_match(line, m, row) || !kRooms.count(m[1].str())) continue;
        Deps& d = table[m[1].str()];
        parse_cell(m[2].str(), d.public_rooms, d.public_libs);
        parse_cell(m[3].str(), d.private_rooms, d.private_libs);
    }
    return table;
}

std::string joined(const Names& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return "{" + out + "}";
}

// Third-party libraries a room gets from the rooms it links publicly or privately: their
// public libraries, and those of their public rooms, transitively.
Names inherited_libs(const Names& rooms, const std::map<std::string, Deps>& deps) {
    Names libs, seen;
    std::vector<std::string> todo(rooms.begin(), rooms.end());
    while (!todo.empty()) {
        const std::string r = todo.back();
        todo.pop_back();
        if (!seen.insert(r).second || !deps.count(r)) continue;
        const Deps& d = deps.at(r);
        libs.insert(d.public_libs.begin(), d.public_libs.end());
        todo.insert(todo.end(), d.public_rooms.begin(), d.public_rooms.end());
    }
    return libs;
}

std::map<std::string, Deps> all_cmake_deps(std::ostringstream& unknown) {
    std::map<std::string, Deps> deps;
    for (const auto& room : kRooms) deps[room] = cmake_deps(room, unknown);
    return deps;
}

TEST(DependencyTable, CMakeLinksWhatTheTableSays) {
    std::ostringstream unknown, wrong;
    const auto cmake = all_cmake_deps(unknown);
    EXPECT_TRUE(unknown.str().empty()) << "targets the test cannot name (add them to kThirdPartyTargets):"
                                       << unknown.str();
    const auto doc = documented_deps();
    for (const auto& room : kRooms) {
        if (!doc.count(room)) {
            wrong << "  " << room << ": no row in the table\n";
            continue;
        }
        const Deps& c = cmake.at(room);
        const Deps& d = doc.at(room);
        Names public_rooms = d.public_rooms;
        if (room == "app") {  // "every room", linked privately: it is an executable
            public_rooms.clear();
            Names every(kRooms);
            every.erase("app");
            if (c.private_rooms != every) wrong << "  app links " << joined(c.private_rooms) << ", not every room\n";
        } else {
            if (c.public_rooms != public_rooms)
                wrong << "  " << room << " public rooms: CMake " << joined(c.public_rooms) << ", table "
                      << joined(public_rooms) << "\n";
            if (c.private_rooms != d.private_rooms)
                wrong << "  " << room << " private rooms: CMake " << joined(c.private_rooms) << ", table "
                      << joined(d.private_rooms) << "\n";
        }
        // Public libraries: those a room's public headers need beyond what its public rooms give.
        Names own_public;
        const Names given = inherited_libs(c.public_rooms, cmake);
        for (const auto& lib : c.public_libs)
            if (!given.count(lib)) own_public.insert(lib);
        if (own_public != d.public_libs)
            wrong << "  " << room << " public third-party: CMake " << joined(own_public) << ", table "
                  << joined(d.public_libs) << "\n";
        if (c.private_libs != d.private_libs)
            wrong << "  " << room << " private third-party: CMake " << joined(c.private_libs) << ", table "
                  << joined(d.private_libs) << "\n";
    }
    EXPECT_TRUE(wrong.str().empty()) << "docs/architecture.md's table and the CMake files disagree:\n" << wrong.str();
}

// The room whose public headers hold `header` (foldcast/ROOM/...).
std::string owning_room(const std::string& header) {
    const std::size_t slash = header.find('/', 9);
    return slash == std::string::npos ? "" : header.substr(9, slash - 9);
}

TEST(DependencyTable, RoomsIncludeOnlyWhatTheyLink) {
    std::ostringstream unknown, wrong;
    const auto cmake = all_cmake_deps(unknown);
    static const std::regex include(R"(#\s*include\s*[<"]([^>"]+)[>"])");
    for (const auto& room : kRooms) {
        const Deps& c = cmake.at(room);
        Names rooms_allowed = c.public_rooms;
        rooms_allowed.insert(c.private_rooms.begin(), c.private_rooms.end());
        rooms_allowed.insert(room);
        const Names public_libs_allowed = [&] {
            Names l = c.public_libs;
            const Names given = inherited_libs(c.public_rooms, cmake);
            l.insert(given.begin(), given.end());
            return l;
        }();
        Names libs_allowed = public_libs_allowed;
        libs_allowed.insert(c.private_libs.begin(), c.private_libs.end());
        const Names given_all = inherited_libs(rooms_allowed, cmake);
        libs_allowed.insert(given_all.begin(), given_all.end());
        for (const auto& file : cpp_files(FOLDCAST_SOURCE_DIR, {room})) {
            const std::string relative = fs::relative(file, FOLDCAST_SOURCE_DIR).string();
            const bool public_header = relative.find("/include/") != std::string::npos;
            const std::string text = read_text(file);
            for (auto it = std::sregex_iterator(text.begin(), text.end(), include); it != std::sregex_iterator();
                 ++it) {
                const std::string header = (*it)[1].str();
                if (header.rfind("foldcast/", 0) == 0) {
                    const std::string owner = owning_room(header);
                    const Names& allowed = public_header ? c.public_rooms : rooms_allowed;
                    if (owner != room && !allowed.count(owner))
                        wrong << "  " << relative << " includes " << header << " (room " << owner << ")\n";
                    continue;
                }
                const std::string first = header.substr(0, header.find('/'));
                const auto lib = kThirdPartyHeaders.find(first);
                if (lib == kThirdPartyHeaders.end()) continue;  // the standard library, the system
                const Names& allowed = public_header ? public_libs_allowed : libs_allowed;
                if (!allowed.count(lib->second))
                    wrong << "  " << relative << " includes " << header << " (" << lib->second << ", not linked"
                          << (public_header ? " publicly" : "") << ")\n";
            }
        }
    }
    EXPECT_TRUE(wrong.str().empty()) << "includes of rooms or libraries the CMake files do not link:\n" << wrong.str();
}

TEST(DependencyTable, PublicHeadersSitUnderTheirRoomsName) {
    std::ostringstream wrong;
    int headers = 0;
    for (const auto& room : kRooms) {
        const fs::path include = fs::path(FOLDCAST_SOURCE_DIR) / room / "include";
        if (!fs::exists(include)) continue;
        for (const auto& entry : fs::recursive_directory_iterator(include)) {
            if (!entry.is_regular_file()) continue;
            ++headers;
            const fs::path relative = fs::relative(entry.path(), include);
            if (relative.parent_path() != fs::path("foldcast") / room || relative.extension() != ".hpp")
                wrong << "  " << room << "/include/" << relative.string() << "\n";
        }
    }
    EXPECT_GT(headers, 20);
    EXPECT_TRUE(wrong.str().empty()) << "public headers outside <room>/include/foldcast/<room>/NAME.hpp:\n"
                                     << wrong.str();
}

}  // namespace dependency_table_test
