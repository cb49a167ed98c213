// KITTI calibration files: the raw-data files (calib_cam_to_cam.txt, calib_velo_to_cam.txt,
// calib_imu_to_velo.txt) and the odometry calib.txt. Every reader throws io::FileError naming the file,
// the key and the problem (missing file, missing key, wrong number of values, non-numeric or NaN value).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/calibration.h"
#include "io/file_error.h"

namespace semap::io {

// A "key: v1 v2 ..." text file as KITTI writes its calibration. Keys whose values are not all numbers
// (e.g. calib_time) are kept as text. Immutable after construction; const methods are thread-safe.
class KeyValueFile {
 public:
  // Reads `path`; throws FileError when it is missing or a line has no "key:".
  explicit KeyValueFile(const std::filesystem::path& path);

  const std::filesystem::path& path() const { return path_; }
  bool Has(const std::string& key) const { return values_.count(key) > 0; }
  // The numbers of `key`, exactly `count` of them, all finite; throws FileError naming path and key.
  std::vector<double> Numbers(const std::string& key, size_t count) const;
  Eigen::Matrix<double, 3, 4> Matrix34(const std::string& key) const;
  Eigen::Matrix3d Matrix33(const std::string& key) const;
  Eigen::Vector3d Vector3(const std::string& key) const;

 private:
  std::filesystem::path path_;
  std::map<std::string, std::string> values_;  // key → the text after ':'
};

// Rectified intrinsics and baseline from the projection matrices of the left and right rectified cameras:
// fx = P[0,0], fy = P[1,1], cx = P[0,2], cy = P[1,2], baseline_m = (P_left[0,3] - P_right[0,3]) / fx.
// Image size is left 0 (set from the images). Throws FileError(path) when the result is not a valid rig.
StereoCalibration StereoFromProjections(const Eigen::Matrix<double, 3, 4>& p_left,
                                        const Eigen::Matrix<double, 3, 4>& p_right,
                                        const std::filesystem::path& path);

// Throws FileError naming `path` and `key` unless the intrinsics of `s` fit its image (width_px × height_px,
// set from the images): the principal point inside the image, the focal lengths between 0.05 and 1000 times
// the larger image side. A typo there (cx = 1e9, cy = 1728540) would otherwise abort on an assertion,
// allocate gigabytes or map nonsense.
void CheckIntrinsicsFitImage(const StereoCalibration& s, const std::filesystem::path& path,
                             const std::string& key);

// [R | T] of a raw calibration file ("R:" 9 values row-major, "T:" 3 values) as a rigid transform.
Pose3d ReadRigidTransform(const std::filesystem::path& path);

// The rig of a KITTI raw date folder (or of the stereo-2015 subset): left = cam 2, right = cam 3.
struct RawCalibration {
  StereoCalibration stereo;              // from P_rect_02 / P_rect_03
  std::optional<Pose3d> cam2_from_velo;  // T(x = P_rect_02[0,3]/fx) · R_rect_00 · [R|T]_velo_to_cam
  std::optional<Pose3d> cam2_from_imu;   // cam2_from_velo · [R|T]_imu_to_velo
};

// Reads `dir`/calib_cam_to_cam.txt (required) and, when present, calib_velo_to_cam.txt and
// calib_imu_to_velo.txt. A present file with a missing key or bad value is an error.
RawCalibration ReadRawCalibration(const std::filesystem::path& dir);

// Which stereo pair of an odometry sequence is read.
enum class OdometryPair { kGray, kColor };

// The rig of a KITTI odometry sequence from calib.txt (P0..P3, optional Tr = velodyne → rectified cam 0).
struct OdometryCalibration {
  StereoCalibration stereo;                   // P0/P1 (gray) or P2/P3 (colour)
  Pose3d cam_from_cam0 = Pose3d::Identity();  // gray: identity; colour: T(x = P2[0,3]/fx)
  std::optional<Pose3d> cam_from_velo;        // cam_from_cam0 · Tr, when Tr is present
};

// Reads an odometry calib.txt for the chosen pair.
OdometryCalibration ReadOdometryCalibration(const std::filesystem::path& calib_txt, OdometryPair pair);

// A pure translation along x (the rectified cameras differ only by this).
Pose3d TranslationX(double x_m);

}  // namespace semap::io
