#pragma once
// Private to the subdiv sources: OpenSubdiv is linked privately, so its types stay out of
// the public headers.
#include <memory>
#include <vector>

#include <opensubdiv/far/topologyRefiner.h>

namespace chs {

// Catmull-Clark topology of a polygon mesh (faces of >= 3 corners, listed back to back in
// face_vertices with face_sizes[f] corners each, counter-clockwise seen from the normal side),
// with the boundary rule used throughout the shell code: EDGE_AND_CORNER, i.e. boundary
// edges are infinitely sharp creases (the limit boundary is the cubic B-spline of the
// boundary points) and valence-2 boundary corners are interpolated.
//
// Throws InputError for an empty mesh, indices out of range, repeated corners, a vertex on
// no face, an edge shared by more than two faces or run twice in the same direction (the
// orientation flips there), and a vertex whose faces form more than one fan.
std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> makeCatmarkRefiner(
    int num_vertices, const std::vector<int>& face_sizes, const std::vector<int>& face_vertices);

}  // namespace chs
