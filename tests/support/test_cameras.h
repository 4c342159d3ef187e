// Cameras for the tests. Distortion: the same coefficients wherever a test needs "a
// distorted pinhole" or "a slightly distorted fisheye", so that tests of projection and of its
// files see the same models. The Kinect's pinhole and the default rig's upward fisheye with its
// mount, for the tests that need those cameras themselves.
#pragma once

#include <numbers>

#include <Eigen/Core>
#include <catch2/catch.hpp>

#include "common/camera_models.h"
#include "common/pose.h"

namespace corridorsim::test {

/// An ASUS Xtion / Kinect v1 depth camera: 640 x 480, f = 525 px, centre (319.5, 239.5).
inline PinholeRadTan Kinect() {
  PinholeRadTan k;
  k.width = 640;
  k.height = 480;
  k.fx = k.fy = 525.0;
  k.cx = 319.5;
  k.cy = 239.5;
  return k;
}

/// The default rig's upward camera: Kannala-Brandt 640x480, 110 deg.
inline KannalaBrandt UpwardFisheye() {
  return KannalaBrandt::FromFov(640, 480, 110.0 * std::numbers::pi / 180.0);
}

/// The default rig's upward camera mount, at (-0.05, 0, 0.4) m, pitched up 90 deg:
/// render::Mount{-0.05, 0, 0.4, yaw 0, pitch 90, roll 0}. Image x (right) = the robot's -y,
/// image y (down) = its +x, the optical axis up.
inline SE3 UpwardMount() {
  Eigen::Matrix3d r;
  r.col(0) = Eigen::Vector3d(0, -1, 0);
  r.col(1) = Eigen::Vector3d(1, 0, 0);
  r.col(2) = Eigen::Vector3d(0, 0, 1);
  return SE3(r, Eigen::Vector3d(-0.05, 0.0, 0.4));
}

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
