#pragma once
// Isometric prediction (profile `cascade`, docs/codec.md): cloth hardly stretches, so a
// vertex whose parallelogram corners a and b are decoded lies close to the circle of points
// at its predicted distances from a and from b.  The prediction is the point of that circle
// nearest the spatial prediction's, and the residual is quantised along three orthonormal axes:
// the circle's tangent (the fold's hinge angle, what the motion really changes), the
// direction to the circle's centre and the axis a -> b (both only stretch), so two of the
// three quantised values are nearly always 0.
//
// Bit for bit alike on every machine and in WebAssembly: doubles with only +, -, *, / and
// sqrt (correctly rounded by IEEE 754), never fused into multiply-adds (the file is built
// with -ffp-contract=off), and every conversion back to integers clamped first.
#include <cstddef>
#include <cstdint>

namespace foldcast::codec {

// Grid coordinates of the point a frame's quantised residuals are measured from, and the
// three axes they are measured along.
struct IsometricFrame {
    double origin[3];
    double axis[3][3];
};

// What the frame of a vertex v is made from, all grid coordinates: p0 its temporal plus
// spatial prediction, xa and xb its corners a and b as decoded, lv, la and lb v, a
// and b in the decoded frame whose edge lengths are kept.
struct IsometricInputs {
    std::int64_t p0[3], xa[3], xb[3], lv[3], la[3], lb[3];
};

// The frame, or false where the circle is not defined (a and b on one grid point, or p0 on
// their axis): the caller quantises along the grid's axes instead.
bool isometric_frame(const IsometricInputs& in, IsometricFrame& out);

// The inputs of vertex v predicted at p0, with parallelogram corners a and b, from a frame's
// decoded coordinates (only vertices before v are read) and the frame whose lengths are
// kept, each 3 values per vertex.
template <typename Decoded>
IsometricInputs isometric_inputs(std::size_t v, std::size_t a, std::size_t b, const std::int64_t p0[3],
                                 const Decoded* decoded, const std::int32_t* lengths) {
    IsometricInputs in;
    for (std::size_t k = 0; k < 3; ++k) {
        in.p0[k] = p0[k];
        in.xa[k] = decoded[3 * a + k];
        in.xb[k] = decoded[3 * b + k];
        in.lv[k] = lengths[3 * v + k];
        in.la[k] = lengths[3 * a + k];
        in.lb[k] = lengths[3 * b + k];
    }
    return in;
}

// Values beyond this are clamped before any conversion to an integer: corrupt data can then
// only produce a coordinate outside the grid, which the decoder rejects.
constexpr double kIsometricClamp = 4.0e12;

// The quantised residual of target (grid coordinates) along the frame's axes, step s.
void isometric_quantise(const IsometricFrame& frame, const std::int32_t target[3], std::int64_t s, std::int64_t q[3]);

// The grid coordinates that the quantised values q stand for (rounded to the grid).
void isometric_reconstruct(const IsometricFrame& frame, const std::int64_t q[3], std::int64_t s, std::int64_t out[3]);

}  // namespace foldcast::codec
