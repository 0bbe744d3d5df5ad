#pragma once
// Local topology of the VTK tetrahedron and hexahedron: outward faces and, for
// the hexahedron, the three edge neighbours of each corner. Outward means the
// face normal (b-a)x(c-a) (triangle) or (c-a)x(d-b) (quad) points out of a
// positively oriented element.
#include <array>

namespace adamss::preprocess {

inline constexpr std::array<std::array<int, 3>, 4> kTetFaces{{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}};

inline constexpr std::array<std::array<int, 4>, 6> kHexFaces{
    {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};

/// Corner code (bit 0 = +x, bit 1 = +y, bit 2 = +z) of each VTK hexahedron node.
inline constexpr std::array<int, 8> kHexCornerCode{0, 1, 3, 2, 4, 5, 7, 6};

/// Neighbours of each hex corner along local x, y, z (VTK order:
/// 0 (000), 1 (100), 2 (110), 3 (010), 4 (001), 5 (101), 6 (111), 7 (011)).
inline constexpr std::array<std::array<int, 3>, 8> kHexNeighbour{
    {{1, 3, 4}, {0, 2, 5}, {3, 1, 6}, {2, 0, 7}, {5, 7, 0}, {4, 6, 1}, {7, 5, 2}, {6, 4, 3}}};

}  // namespace adamss::preprocess
