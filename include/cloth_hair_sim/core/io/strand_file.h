#pragma once
#include <string>

#include "cloth_hair_sim/core/rod/groom.h"

namespace chs {

// Strand files: polylines from root to tip, in the file's units (the caller scales them).
//
// Text strands (any extension but .hair), one strand after another:
//   # a comment (from '#' to the end of the line); blank lines are skipped
//   3                 the strand's vertex count, then that many lines "x y z"
//   0 0 0
//   0 0 -0.05
//   0 0 -0.1
//
// Cem Yuksel's HAIR binary format (.hair, www.cemyuksel.com/research/hairmodels), little
// endian: a 128-byte header
//   char[4] "HAIR", uint32 strands, uint32 points, uint32 arrays (bit 0 segments, 1 points,
//   2 thickness, 3 transparency, 4 colours), uint32 default segments, float default thickness,
//   float default transparency, float[3] default colour, char[88] information,
// then in that order the arrays present: uint16 segments per strand, float[3] per point,
// float thickness per point, float transparency per point, float[3] colour per point. Only the
// points and segments are read; a file without points is refused.
//
// PLY (.ply): vertices and edges, ascii or binary little endian, each strand a chain of edges
// read from its lower-numbered end (what the simulate tool writes for hair; details in
// src/core/io/strand_ply.h).
//
// All throw InputError naming the file and the problem: missing, unreadable, truncated, a count
// that disagrees, or strands that rod::checkStrands refuses (NaN, zero length, duplicate
// vertices, beyond the documented limits).
rod::Polylines readStrandFile(const std::string& path);

}  // namespace chs
