#pragma once
// What the dataset's files share (dataset.cpp: the job, its folder and manifest; dataset_poses.cpp:
// the robot's poses; dataset_world.cpp: a world's frames rendered; dataset_coco.cpp: the COCO
// annotations): the command line as the place of a refused argument, and the rounding of the
// numbers its JSON files hold. Internal to harness/workbench/.

#include "common/error.h"
#include "common/io/stable_json.h"

namespace corridorsim::dataset_internal {

inline const SourceLocation kCommandLine{"command line", 0, 0};

inline double Px(double v) { return RoundToStep(v, json_steps::kPx); }
inline double Fraction(double v) { return RoundToStep(v, 1e6); }
inline double Metres(double v) { return RoundToStep(v, json_steps::kMetres); }
inline double Deg(double v) { return RoundToStep(v, json_steps::kDeg); }
inline double Ratio(double v) { return RoundToStep(v, json_steps::kRatio); }

}  // namespace corridorsim::dataset_internal
