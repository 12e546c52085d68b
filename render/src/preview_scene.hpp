#pragma once
// Turns the path tracer's view of a frame (studio geometry, lit scene, camera) into the
// rasteriser's, so previews and renders show the same thing.
#include "foldcast/render.hpp"
#include "foldcast/render/preview.hpp"
#include "tracer.hpp"

namespace foldcast::render {

// `geometry` must outlive the returned scene (it points at its meshes).
PreviewScene make_preview_scene(const SceneSpec& lit_scene, const FrameGeometry& geometry,
                                const std::vector<Mesh>& studio_meshes, const Camera& camera);
// The studio meshes of `geometry` as plain meshes, for make_preview_scene.
std::vector<Mesh> studio_meshes(const FrameGeometry& geometry);

// One frame through the rasteriser, as a RenderResult (beauty, and the depth AOV if asked).
RenderResult preview_frame(PreviewRenderer& renderer, const SceneSpec& lit_scene,
                           const FrameGeometry& geometry, const Camera& camera,
                           const std::vector<Aov>& aovs);

}  // namespace foldcast::render
