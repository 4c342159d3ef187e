// Cameras for the tests. Distortion: the same coefficients wherever a test needs "a
// distorted pinhole" or "a slightly distorted fisheye", so that tests of projection and of its
// files see the same models.
#pragma once

#include <catch2/catch.hpp>

#include "common/camera_models.h"

namespace corridorsim::test {

/// `camera` with the radial-tangential distortion of a calibrated wide webcam / RGB-D colour
/// camera (k1, k2, p1, p2, k3 in OpenCV's order: -0.28, 0.07, 1e-4, -2e-4, -0.005).
inline PinholeRadTan WithWebcamDistortion(PinholeRadTan camera) {
  camera.k1 = -0.28;
  camera.k2 = 0.07;
  camera.p1 = 1e-4;
  camera.p2 = -2e-4;
  camera.k3 = -0.005;
  return camera;
}

/// `camera` with small equidistant distortion (k1..k4: 0.02, -0.005, 0.001, -0.0002).
inline KannalaBrandt WithSmallFisheyeDistortion(KannalaBrandt camera) {
  camera.k1 = 0.02;
  camera.k2 = -0.005;
  camera.k3 = 0.001;
  camera.k4 = -0.0002;
  return camera;
}

/// CHECKs every field of `actual` against `expected`.
inline void CheckIntrinsics(const CameraIntrinsics& actual, const CameraIntrinsics& expected) {
  CHECK(actual.model == expected.model);
  CHECK(actual.width == expected.width);
  CHECK(actual.height == expected.height);
  CHECK(actual.fx == expected.fx);
  CHECK(actual.fy == expected.fy);
  CHECK(actual.cx == expected.cx);
  CHECK(actual.cy == expected.cy);
  CHECK(actual.distortion == expected.distortion);
}

}  // namespace corridorsim::test
