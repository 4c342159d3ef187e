#pragma once
// The project's plain images (common/image.h: RGB(A), row 0 on top) as OpenCV matrices and back,
// for the detectors of slam/features/. Views share the image's bytes (no copy); conversions that
// change the channel layout copy once.

#include <opencv2/core.hpp>

#include "common/image.h"

namespace corridorsim::slam {

/// A cv::Mat header over `image`'s bytes (CV_8UC1/3/4, channels in the image's RGB(A) order, not
/// OpenCV's BGR): no copy. It must not outlive `image`; it is for reading only (cv::Mat has no
/// const view, so writing through it would change `image`). Aborts (a bug) on an inconsistent
/// image (size, channel count 1, 3 or 4).
cv::Mat MatView(const Image8& image);

/// A CV_32FC1 header over `image`'s values (no copy); the same rules as MatView.
cv::Mat MatView(const ImageF& image);

/// The image as 8-bit grey (CV_8UC1, ITU-R BT.601 weights as cv::cvtColor): a view of a
/// one-channel image (no copy), a new matrix for RGB and RGBA.
cv::Mat GreyMat(const Image8& image);

/// The image as OpenCV's BGR (CV_8UC3): a new matrix (RGB swapped, grey replicated, alpha dropped).
cv::Mat BgrMat(const Image8& image);

/// An RGB Image8 from a CV_8UC3 BGR matrix, or a one-channel Image8 from a CV_8UC1 matrix (one
/// copy). Aborts (a bug) on another type.
Image8 ImageFromMat(const cv::Mat& bgr_or_grey);

}  // namespace corridorsim::slam
