// What the door plate detector and reader tests share: the shipped models (models/, loaded once
// per test binary) and the ground truth of a plate in a rendered lateral view.
#pragma once

#include "render/frame_truth.h"
#include "slam/features/door_plates.h"
#include "tests/support/lateral_views.h"

namespace corridorsim::test {

/// The detector's and reader's models as shipped in models/.
inline const slam::DoorPlateModels& ShippedModels() {
  static const slam::DoorPlateModels models = slam::DoorPlateModels::Load();
  return models;
}

/// The box of the room number's text on plate truth `p`.
inline slam::BoxPx NumberBox(const render::PlateTruth& p) {
  return slam::BoxPx{p.number_bbox_min_px.x(), p.number_bbox_min_px.y(), p.number_bbox_max_px.x(),
                     p.number_bbox_max_px.y()};
}

/// The truth of plate `id` in `view`, or nullptr where the view has none.
inline const render::PlateTruth* TruthOf(const LateralView& view, int id) {
  for (const auto& p : view.truth.plates) {
    if (p.id == id) return &p;
  }
  return nullptr;
}

}  // namespace corridorsim::test
