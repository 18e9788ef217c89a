// What a side of the background grid is: free, fixed, roller (no normal motion) or a
// frictional wall (Thesis eq. 5.8-5.11).
#pragma once

namespace skred {

enum class BoundaryKind { Free, Fixed, Roller, Friction };

struct BoundarySide {
  BoundaryKind kind = BoundaryKind::Free;
  double friction = 0.0;  // Coulomb coefficient mu (Thesis eq. 5.8), Friction only
};

}  // namespace skred
