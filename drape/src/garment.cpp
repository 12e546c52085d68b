// The garment of one solve: the material grid on the fold surface with UVs, normals,
// fold signs, its fixed support vertices and its stretch, relaxed towards isometry.
#include <algorithm>

#include "foldcast/drape/drape.hpp"
#include "foldcast/drape/relax.hpp"
#include "fold_surface.hpp"

namespace foldcast::drape {

Garment build_garment(const ClothParams& params, const FoldSolution& solution, GridSize grid, bool relax) {
    validate(params);
    detail::validate_grid(grid);
    Garment g;
    detail::garment_positions(params, solution, grid, g.mesh.positions, &g.fold_sign);
    g.mesh.topology.triangles = detail::grid_triangles(grid);
    g.mesh.topology.uvs = detail::grid_uvs(params, grid);
    g.support_vertices = detail::support_columns(params, grid);
    g.stretch_analytical = detail::grid_stretch(g.mesh.positions, params, grid);
    g.stretch = g.stretch_analytical;
    if (relax) {
        const std::vector<Vec3f> model = g.mesh.positions;
        const RelaxReport report = GridRelaxer(params, grid, g.support_vertices).relax(g.mesh.positions, model);
        g.stretch = report.after;
        g.relax_iterations = report.iterations;
        if (solution.zmax_m > 0.0)  // the relaxed fold's side, as the model's: z / zmax
            for (std::size_t k = 0; k < g.fold_sign.size(); ++k)
                g.fold_sign[k] = std::clamp(float(g.mesh.positions[k].z() / solution.zmax_m), -1.0f, 1.0f);
    }
    g.mesh.normals = vertex_normals(g.mesh.positions, g.mesh.topology.triangles);
    return g;
}

}  // namespace foldcast::drape
