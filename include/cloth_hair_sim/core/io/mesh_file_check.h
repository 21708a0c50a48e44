#pragma once
#include <string>

namespace chs {

// Refuses a mesh file that does not parse whole, before assimp reads it: assimp skips what it
// cannot read (a face cut in the middle becomes a line and is dropped, a short PLY ends early),
// so a truncated or damaged file would load silently with the faces before the damage.
// OBJ: every statement must be well formed (vertices with 3-7 numbers, faces with at least 3
// references to vertices already defined, known keywords only), and the last line must end (a
// file cut anywhere in its last statement lacks the line end). PLY (ASCII and binary): the body
// must hold every element the header declares. Other formats pass (assimp's own checks apply).
// Throws InputError naming the file, the line (or element) and what is wrong.
void checkMeshFileComplete(const std::string& path);

}  // namespace chs
