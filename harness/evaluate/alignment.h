#pragma once
// Aligning an estimated trajectory to the truth before it is scored (docs/evaluation.md): none,
// SE(2) (a rotation about z and an x-y translation: a planar system's unknown start), SE(3) and
// Sim(3) (a monocular system's unknown scale), each the least-squares fit of the associated
// positions in closed form (Umeyama 1991, "Least-squares estimation of transformation parameters
// between two point patterns", eqs. 40-42; Horn 1987 without scale).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/enum_names.h"

namespace corridorsim::evaluate {

enum class Alignment { kNone, kSE2, kSE3, kSim3 };
inline constexpr Alignment kAllAlignments[] = {Alignment::kNone, Alignment::kSE2, Alignment::kSE3,
                                               Alignment::kSim3};

/// Each alignment's name (header-only: the command-line parser reads them).
inline constexpr EnumName<Alignment> kAlignmentNames[] = {{Alignment::kNone, "none"},
                                                          {Alignment::kSE2, "se2"},
                                                          {Alignment::kSE3, "se3"},
                                                          {Alignment::kSim3, "sim3"}};

/// "none", "se2", "se3", "sim3".
inline std::string AlignmentName(Alignment alignment) { return NameOf(kAlignmentNames, alignment); }

/// From its name; nullopt for anything else.
inline std::optional<Alignment> AlignmentFromName(const std::string& name) {
  for (const EnumName<Alignment>& a : kAlignmentNames) {
    if (a.name == name) return a.value;
  }
  return std::nullopt;
}

/// x -> scale * rotation * x + translation.
struct Similarity {
  double scale = 1.0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const {
    return scale * (rotation * x) + translation;
  }
};

/// The transform of `alignment` that minimises sum |truth_i - T(estimate_i)|^2 over the pairs
/// (the two vectors have equal size). Fails (nullopt, `*why` says why) with fewer pairs than it
/// needs (se2: 2, se3 and sim3: 3) or positions too degenerate to fix it: se2 needs two distinct
/// x-y positions; se3 and sim3 positions that do not lie on one line (a rotation about it would be
/// free). kNone gives the identity.
std::optional<Similarity> Align(Alignment alignment, const std::vector<Eigen::Vector3d>& estimate,
                                const std::vector<Eigen::Vector3d>& truth, std::string* why);

}  // namespace corridorsim::evaluate
