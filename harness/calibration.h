#pragma once
// What a robot knows about itself, as the pipelines receive it: the nominal robot and the
// cameras as configured (never the simulator's real, perturbed values).

#include "harness/scenario.h"
#include "slam/pipeline.h"

namespace corridorsim {

slam::Calibration CalibrationOf(const Scenario& scenario);

}  // namespace corridorsim
