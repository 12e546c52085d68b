// The garment of one solve: the material grid on the fold surface with UVs, normals,
// fold signs, its fixed support vertices and its stretch.
#include "foldcast/drape.hpp"
#include "fold_surface.hpp"

namespace foldcast::drape {

Garment build_garment(const ClothParams& params, const FoldSolution& solution, GridSize grid) {
    validate(params);
    detail::validate_grid(grid);
    Garment g;
    detail::garment_positions(params, solution, grid, g.mesh.positions, &g.fold_sign);
    g.mesh.topology.triangles = detail::grid_triangles(grid);
    g.mesh.topology.uvs = detail::grid_uvs(params, grid);
    g.mesh.normals = vertex_normals(g.mesh.positions, g.mesh.topology.triangles);
    g.support_vertices = detail::support_columns(params, grid);
    g.stretch = detail::grid_stretch(g.mesh.positions, params, grid);
    return g;
}

}  // namespace foldcast::drape
