#pragma once
// What drape, decode and export print after writing a .glb, and the output name check they
// share.
#include <string>

#include "foldcast/export/gltf.hpp"

namespace foldcast::app {

// Throws InputError unless `path` ends in .glb (any case).
void require_glb_extension(const std::string& path);
bool is_glb(const std::string& path);
void print_glb_summary(const std::string& path, const gltf::GlbSummary& summary, bool json, const std::string& look);

}  // namespace foldcast::app
