#pragma once
// Turns the path tracer's view of a frame (studio geometry, lit scene, camera) into the
// rasteriser's, so previews and renders show the same thing.
#include "foldcast/render/render.hpp"
#include "foldcast/preview/preview.hpp"

namespace foldcast::preview {

// `geometry` must outlive the returned scene (it points at its meshes).
PreviewScene make_preview_scene(const SceneSpec& lit_scene, const FrameGeometry& geometry,
                                const std::vector<Mesh>& studio_meshes, const Camera& camera);
// The studio meshes of `geometry` as plain meshes, for make_preview_scene.
std::vector<Mesh> studio_meshes(const FrameGeometry& geometry);

}  // namespace foldcast::preview
