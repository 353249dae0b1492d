// Meshes: the notched plate of SPEC 1 generated with Gmsh's C++ API, a box (bar) mesh for
// tests, and import of .msh / .vtu tetrahedral meshes. All return reference configurations.
#pragma once

#include <cstdint>
#include <string>

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include "scene.hpp"

namespace brittle {

/// Notched plate (SPEC 1): 2-D triangulation of the outline with the wedge notch, crack line
/// from (a, 0) to (L, 0) embedded, optional finer band |y| < band, extruded in `layers` layers
/// and split into linear tets. notch_depth = 0 gives an un-notched plate.
/// Points and cells come in a locality-preserving order (see renumber_for_locality).
vtkSmartPointer<vtkUnstructuredGrid> generate_plate_mesh(const GeometryParams& g,
                                                         const MeshParams& m);

/// Box [0,lx] x [-ly/2, ly/2] x [0,lz] of linear tets with element size about h (Gmsh).
vtkSmartPointer<vtkUnstructuredGrid> generate_box_mesh(double lx, double ly, double lz, double h);

/// Reads a Gmsh .msh or VTK .vtu file holding linear tetrahedra (other cells are ignored).
/// Inverted tets are reoriented; zero-volume tets, unreadable files and files without tets
/// throw brittle::Error naming the file (and the cell).
vtkSmartPointer<vtkUnstructuredGrid> read_mesh(const std::string& path);

/// Moves every node off the mesh's lateral boundary (boundary faces whose normal is not along
/// z) in the x-y plane by up to `fraction` of its shortest in-plane edge, in a direction and by
/// an amount drawn from a hash of its x, y and the seed: nodes above one another move together,
/// and the same scene gives the same mesh (nodal perturbation against mesh-aligned crack
/// paths; docs/mesh.md). Throws brittle::Error if a tet would turn over.
void perturb_mesh(vtkUnstructuredGrid& grid, double fraction, std::uint64_t seed);

/// The scene's mesh: read_mesh(scene.mesh.file) if set, else generate_plate_mesh; then
/// perturb_mesh if mesh.perturb > 0.
vtkSmartPointer<vtkUnstructuredGrid> make_mesh(const Scene& scene);

/// Reorders cells along a space-filling curve of their centroids and numbers points by
/// first use in that cell order, so that neighbouring elements share cache lines.
void renumber_for_locality(vtkUnstructuredGrid& grid);

}  // namespace brittle
