#pragma once
// P1 section 5's feature-based map (Fig. 12d): room number -> the estimated position of its door
// plate with the estimate's covariance and the pipeline's landmark id, so that a goal can be
// named by room number. It leaves as JSON text (slam/ writes no files; the harness writes
// maps/<pipeline>_semantic.json), and ParseSemanticMap reads that text back (`corridorsim where`).
//
//   {"format": "corridorsim.semantic_map", "version": 1, "frame": "world",
//    "rooms": [{"room": "101", "landmark_id": 7, "position_m": [x, y, z],
//               "covariance_m2": [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]}, ...]}
//
// Rooms are sorted by room number (numbers by value: "9" before "10"; other labels after them,
// by bytes). A planar estimate has a 2x2 covariance over (x, y).

#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "slam/pipeline.h"

namespace corridorsim::slam {

struct SemanticMapEntry {
  std::string room;      // room number as read on the plate, unique in a map
  int landmark_id = -1;  // the pipeline's landmark
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();  // m
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();         // m^2
  bool planar = false;  // only the (x, y) block of the covariance is estimated (and written)
};

/// Bounds of what the parser accepts (and the writer may produce).
inline constexpr std::size_t kSemanticMapMaxBytes = 16u << 20;
inline constexpr std::size_t kSemanticMapMaxRooms = 100000;
inline constexpr std::size_t kSemanticMapMaxRoomChars = 32;
inline constexpr double kSemanticMapMaxAbsM = 1e6;  // |coordinate| and sqrt|covariance entry|

/// The order of rooms in a map: numbers by value, then other labels by bytes.
bool RoomNumberLess(const std::string& a, const std::string& b);

/// The semantic map of a pipeline's landmarks: every door plate with a recognised room number.
/// Where two plates carry one number the one with the smaller horizontal variance (x + y) wins
/// (the smaller id on a tie).
std::vector<SemanticMapEntry> SemanticMapFromLandmarks(
    const std::vector<LandmarkEstimate>& landmarks);

/// The JSON text (2-space indents, one trailing newline) of `entries` sorted by room number.
/// Room numbers must be unique, non-empty and at most kSemanticMapMaxRoomChars long (a bug
/// otherwise).
std::string SemanticMapToJson(std::vector<SemanticMapEntry> entries);

/// What is wrong with a semantic map's text: where (1-based line and column, 0 when the problem
/// is not at one place of the text), the key ("rooms[2].covariance_m2"; "" for the whole text) and
/// what.
class SemanticMapError : public std::runtime_error {
 public:
  SemanticMapError(int line, int column, std::string key, std::string message);
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }

 private:
  int line_, column_;
  std::string key_, message_;
};

/// The entries of a semantic map's JSON text, in the file's order (which SemanticMapToJson sorted).
/// Strict: unknown, missing, duplicate and mistyped keys, non-finite or out-of-bound numbers,
/// an asymmetric covariance or a negative variance, and repeated room numbers throw
/// SemanticMapError.
std::vector<SemanticMapEntry> ParseSemanticMap(const std::string& text);

}  // namespace corridorsim::slam
