#pragma once
// Local topology of the VTK tetrahedron and hexahedron: outward faces, edges and, for
// the hexahedron, the face and cell diagonals and the three edge neighbours of each corner.
// Outward means the
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

/// Local node pairs of the 6 tetrahedron edges.
inline constexpr std::array<std::array<int, 2>, 6> kTetEdges{{{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}}};
/// Local node pairs of the 12 hexahedron edges: bottom ring, top ring, then the vertical edges.
inline constexpr std::array<std::array<int, 2>, 12> kHexEdges{
    {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}}};
/// Local node pairs of the 12 hexahedron face diagonals (two per face).
inline constexpr std::array<std::array<int, 2>, 12> kHexFaceDiagonals{
    {{0, 2}, {1, 3}, {4, 6}, {5, 7}, {0, 5}, {1, 4}, {1, 6}, {2, 5}, {2, 7}, {3, 6}, {3, 4}, {0, 7}}};
/// Local node pairs of the 4 hexahedron cell diagonals.
inline constexpr std::array<std::array<int, 2>, 4> kHexCellDiagonals{{{0, 6}, {1, 7}, {2, 4}, {3, 5}}};

}  // namespace adamss::preprocess
