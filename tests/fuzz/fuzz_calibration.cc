// Fuzzes the KITTI calibration readers: raw calib_cam_to_cam.txt (with valid velo/imu files beside it),
// the rigid-transform reader and odometry calib.txt.
#include "io/kitti/calibration.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace semap;
  const auto cam = fuzz::WriteInput("calib_cam_to_cam.txt", data, size);
  const auto dir = cam.parent_path();
  static const std::string rigid = "calib_time: x\nR: 1 0 0 0 1 0 0 0 1\nT: 0 0 0\n";
  std::ofstream(dir / "calib_velo_to_cam.txt") << rigid;
  std::ofstream(dir / "calib_imu_to_velo.txt") << rigid;
  try {
    io::ReadRawCalibration(dir);
  } catch (const std::exception&) {
  }
  try {
    io::ReadRigidTransform(cam);
  } catch (const std::exception&) {
  }
  for (auto pair : {io::OdometryPair::kGray, io::OdometryPair::kColor}) {
    try {
      io::ReadOdometryCalibration(cam, pair);
    } catch (const std::exception&) {
    }
  }
  return 0;
}
