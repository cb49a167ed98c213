#include "app/run/odometry_reader.h"

#include <stdexcept>

#include "engine/core/stopwatch.h"
#include "io/output/trajectory_files.h"

namespace semap::app {

void OdometryLog::Add(OdometryRecord record) {
  std::lock_guard<std::mutex> lock(mutex_);
  records_.push_back(std::move(record));
}

std::vector<io::FrameFigure> OdometryLog::Figures(std::int64_t frame_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  // Frames reach the output in reading order: the record is at the end, or near it.
  for (auto it = records_.rbegin(); it != records_.rend(); ++it) {
    if (it->frame_id != frame_id) continue;
    const OdometryResult& r = it->result;
    return {{"odometry_status", static_cast<double>(static_cast<int>(r.status))},
            {"odometry_features", static_cast<double>(r.features)},
            {"odometry_inliers", static_cast<double>(r.inliers)},
            {"odometry_cpu_ms", r.cpu_ms},
            {"odometry_ms", it->wall_ms},
            {"odometry_disparity_offset_px", r.disparity_offset.constant_px},
            {"odometry_disparity_offset_per_row_px", r.disparity_offset.per_row_px},
            {"odometry_keyframe", r.keyframe ? 1.0 : 0.0}};
  }
  return {};
}

std::vector<OdometryRecord> OdometryLog::Records() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return records_;
}

int OdometryLog::failures() const {
  std::lock_guard<std::mutex> lock(mutex_);
  int n = 0;
  for (const auto& r : records_) {
    n += r.result.status == OdometryStatus::kBridged || r.result.status == OdometryStatus::kRestarted;
  }
  return n;
}

OdometryReader::OdometryReader(std::unique_ptr<FrameReader> source, const StereoOdometryOptions& options,
                               bool replace_poses, std::shared_ptr<OdometryLog> log)
    : source_(std::move(source)), options_(options), replace_poses_(replace_poses), log_(std::move(log)) {
  options_.Check();
}

std::optional<Frame> OdometryReader::Next() {
  std::optional<Frame> frame = source_->Next();
  if (!frame) return frame;
  if (!odometry_) {
    odometry_ = std::make_unique<StereoOdometry>(options_, frame->calibration);
    if (frame->world_from_cam) odometry_->SetFirstPose(*frame->world_from_cam);
  }
  const Stopwatch stopwatch;
  OdometryRecord record;
  record.frame_id = frame->id;
  record.timestamp_s = frame->timestamp_s;
  record.result = odometry_->Track(frame->left, frame->right, frame->timestamp_s);
  record.wall_ms = stopwatch.ElapsedMs();
  const OdometryResult result = record.result;
  log_->Add(std::move(record));
  // The rig's rectification offset as the odometry knows it, when the frame's depth is to use it too
  // (offset_in_depth: the map's points and the odometry's poses then share one scale).
  if (options_.offset_in_depth) frame->disparity_offset = result.disparity_offset;
  if (!replace_poses_) return frame;
  if (result.status == OdometryStatus::kBridged || result.status == OdometryStatus::kRestarted) {
    throw std::runtime_error(
        "frame " + std::to_string(frame->id) + ": visual odometry lost track (" + result.problem + "); " +
        (result.status == OdometryStatus::kRestarted ? "tracking restarted on this frame, " : "") +
        "its pose is a constant-velocity guess (in the trajectory), the frame is not mapped");
  }
  frame->world_from_cam = result.world_from_cam;
  return frame;
}

OdometryPlan PlanOdometry(const Config& config, bool has_poses, bool raw_layout, const std::string& dataset) {
  OdometryPlan plan;
  switch (config.pose_input.poses) {
    case PoseSource::kAuto:
      plan.replace_poses = !has_poses;
      break;
    case PoseSource::kFile:
    case PoseSource::kOxts: {
      const bool oxts = config.pose_input.poses == PoseSource::kOxts;
      if (!has_poses || oxts != raw_layout) {
        throw ConfigError(ConfigKey(&Config::pose_input, &PoseInputOptions::poses) + ": " +
                          PoseSourceName(config.pose_input.poses) + ": " + dataset + " has no " +
                          (oxts ? "OXTS poses (oxts/data of a KITTI raw drive)" : "pose file") +
                          "; use auto or odometry");
      }
      break;
    }
    case PoseSource::kOdometry:
      plan.replace_poses = true;
      break;
  }
  plan.run = plan.replace_poses || config.pose_input.compare_odometry;
  return plan;
}

RunOdometry PrepareOdometry(const Config& config, const std::string& dataset) {
  const io::SequenceInfo info = io::DescribeDataset(dataset, config.input);
  RunOdometry odometry;
  odometry.plan = PlanOdometry(config, info.has_poses, info.layout == io::DatasetLayout::kKittiRaw, dataset);
  if (odometry.plan.run) odometry.log = std::make_shared<OdometryLog>();
  return odometry;
}

std::vector<std::filesystem::path> WriteOdometryTrajectory(const OdometryLog& log,
                                                           const std::filesystem::path& dir) {
  const std::vector<OdometryRecord> records = log.Records();
  std::vector<Pose3d> poses;
  std::vector<io::StampedPose> stamped;
  for (const auto& r : records) {
    poses.push_back(r.result.world_from_cam);
    stamped.push_back({r.timestamp_s, r.result.world_from_cam});
  }
  const std::filesystem::path kitti = dir / "poses_odometry.txt";
  const std::filesystem::path tum = dir / "poses_odometry.tum";
  io::WriteKittiPoses(kitti, poses);
  io::WriteTumTrajectory(tum, stamped);
  return {kitti, tum};
}

}  // namespace semap::app
