#pragma once
// Places a loaded garment in the studio: garment frames (optionally turned about their
// vertical axis, which is the same as the camera rig orbiting them), the cyclorama sized to
// clear the garment at every turn, the support hardware and the resolved lights.
#include "foldcast/render/render.hpp"
#include "foldcast/render/tracer.hpp"

namespace foldcast::render {

class StudioSetup {
public:
    StudioSetup(const SceneSpec& scene, GarmentData garment);

    int frame_count() const { return static_cast<int>(garment_.animation.frame_count()); }
    // Garment positions of `frame` turned by `turn_deg` about the vertical axis.
    std::vector<Vec3f> garment_points(int frame, double turn_deg) const;
    // What the auto-framing camera fits: the garment plus the rod and clips (not the
    // wires, which run out of frame).
    std::vector<Vec3f> framing_points(int frame, double turn_deg) const;
    FrameGeometry geometry(int frame, double turn_deg) const;
    // A point on the vertical axis that garment_points turns about.
    const Vec3f& turn_centre() const { return centre_; }
    // The scene with its lights resolved (the studio preset placed around the garment).
    const SceneSpec& lit_scene() const { return scene_; }

private:
    Vec3f turn(const Vec3f& p, double turn_deg) const;
    std::vector<StudioMesh> hardware(const std::vector<Vec3f>& garment_positions) const;

    SceneSpec scene_;
    GarmentData garment_;
    Vec3f centre_;
    float radius_ = 0.0f;
    float bottom_ = 0.0f;
};

}  // namespace foldcast::render
