// A frame's dense depth result over LCM (semap_lcm::depth_frame_part_t), from a depth node to a map node:
// DepthFrameSender cuts the frame into bands of rows, each compressed losslessly (zstd) into one
// self-contained message of at most max_message_bytes; DepthFrameAssembler takes the received datagrams in
// any order, with duplicates, losses and garbage, and gives back each frame once all its bands arrived,
// bit-exact.
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "engine/core/calibration.h"
#include "engine/core/options.h"
#include "io/lcm/mesh_blocks.h"
#include "semap_lcm/depth_frame_part_t.hpp"

struct ZSTD_DCtx_s;

namespace semap::io {

// One frame's depth-stage result, everything the map node needs to build the frame's labelled cloud.
struct DepthFrameMessage {
  std::int64_t frame_id = 0;
  double timestamp_s = 0.0;         // the frame's time in its sequence
  double sensed_unix_s = 0.0;       // when the depth node's sensor delivered it, seconds since the Unix epoch
  std::int64_t first_frame_id = 0;  // the sequence as the depth node plays it: first id and number of frames
  std::int64_t sequence_frames = 0;
  StereoCalibration calibration;  // fx, fy, cx, cy, baseline, width, height
  std::optional<Pose3d> world_from_cam;
  DisparityOffset disparity_offset;
  cv::Mat left;          // CV_8UC3 (BGR) or CV_8UC1, the frame's left image (the mesh's colours)
  cv::Mat disparity_px;  // CV_32F, left's size
  cv::Mat confidence;    // CV_32F, left's size
  cv::Mat labels;        // CV_8UC1 left's size, or empty (no labels)
};

struct DepthFrameOptions {
  int max_message_bytes = 60000;
  // Level 1 encodes a KITTI frame in about 60 % of level 3's time for about 5 % more bytes: the depth
  // node's CPU is the scarcer (bench/RESULTS.md, "Split runs today").
  int zstd_level = 1;
  bool byte_shuffle = true;

  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("max_message_bytes", &max_message_bytes,
            "bound on every depth-frame message, bytes encoded; a frame goes in as many bands of rows as "
            "needed (<= ~65000: one UDP datagram each, so one lost datagram loses one frame only)",
            In(1024, 1 << 24));
    v.Field("zstd_level", &zstd_level, "zstd compression level of the bands (higher: smaller, slower)",
            In(1, 19));
    v.Field("byte_shuffle", &byte_shuffle,
            "store the disparity and confidence planes byte by byte (all first bytes, then all second "
            "bytes, ...) before compressing: smaller on depth maps");
  }
  void Check() const { CheckDeclaredRanges(*this); }
};

// The content format of depth_frame_part_t this code writes and reads.
inline constexpr std::int32_t kDepthFrameFormatVersion = 1;

// Stable 64-bit fingerprint of every field of a calibration (any change of any field changes it).
std::int64_t CalibrationFingerprint(const StereoCalibration& c);

// Bytes of an encoded depth_frame_part_t with these counts (LCM fingerprint included).
std::int64_t DepthFramePartEncodedSize(std::int64_t name_bytes, std::int64_t payload_bytes);

// Decodes a part after checking its counts against its length (before the generated decoder allocates), its
// type fingerprint, its checksum, its version and its header (calibration fingerprint, image size, part and
// row range, finite pose). The payload is not decompressed. Returns nullopt and sets `error` otherwise.
std::optional<semap_lcm::depth_frame_part_t> DecodeDepthFramePart(const void* data, size_t size,
                                                                  std::string* error);

class DepthFrameSender {  // thread-safe: Encode is const and may be called from several threads at once
 public:
  // Checks the options (throws InvalidOption) and the node name (at most 255 bytes).
  DepthFrameSender(const DepthFrameOptions& o, std::int64_t run_id, std::int64_t config_fingerprint,
                   std::string node_name);
  // The frame's parts, in row order, each <= max_message_bytes. Throws std::invalid_argument naming the
  // field on bad input (sizes, types, an invalid calibration or one of another size than `left`), or naming
  // max_message_bytes when a single row does not fit.
  std::vector<EncodedMessage> Encode(const DepthFrameMessage& m) const;
  // A drop notice: frame `frame_id` of the sequence (`first_frame_id`, `sequence_frames`) will not be sent
  // (the node was behind, or the frame failed there), so that a map node need not wait for it. One message,
  // num_parts 0, without image, calibration or payload.
  EncodedMessage EncodeDropped(std::int64_t frame_id, double timestamp_s, std::int64_t first_frame_id,
                               std::int64_t sequence_frames) const;

 private:
  DepthFrameOptions options_;
  std::int64_t run_id_;
  std::int64_t config_fingerprint_;
  std::string node_name_;
};

class DepthFrameAssembler {  // not thread-safe
 public:
  struct Counters {
    std::int64_t parts = 0;        // parts accepted (new bands of a frame)
    std::int64_t duplicates = 0;   // parts already held, or of a frame already completed
    std::int64_t malformed = 0;    // undecodable, damaged, or disagreeing with the frame's first part
    std::int64_t foreign_run = 0;  // of another run id
    std::int64_t refused = 0;      // of another config or calibration fingerprint (TakeRefusals says why)
    std::int64_t frames = 0;       // frames completed
    std::int64_t given_up = 0;     // incomplete frames freed (DropBefore, or beyond max_pending_frames)
    std::int64_t late = 0;         // parts of frames below the last DropBefore or a frame given up
    std::int64_t notices = 0;      // drop notices accepted (TakeDropped gives their frames)
  };
  // run_id: only messages of this run are accepted (others: foreign_run). config_fingerprint: the map node's
  // own; a part with another one is refused. The calibration fingerprint of the first accepted frame is kept;
  // later parts with another one are refused too. At most `max_pending_frames` incomplete frames are held (a
  // full frame's planes each): a new one beyond that gives up the oldest (lowest id).
  DepthFrameAssembler(std::int64_t run_id, std::int64_t config_fingerprint, int max_pending_frames = 4);
  ~DepthFrameAssembler();
  DepthFrameAssembler(const DepthFrameAssembler&) = delete;
  DepthFrameAssembler& operator=(const DepthFrameAssembler&) = delete;

  // One received datagram (any order, duplicates, garbage). Returns the frame when this part completes it.
  std::optional<DepthFrameMessage> Add(const void* data, size_t size);
  // Incomplete frames with id < frame_id are given up (freed); returns their ids, ascending. Later parts of
  // frames below frame_id are counted late and dropped.
  std::vector<std::int64_t> DropBefore(std::int64_t frame_id);
  // Why parts were refused, once per (node, reason) over the assembler's life, each line at most once:
  // "node cam-a: config fingerprint 0x… differs from the map node's 0x…".
  std::vector<std::string> TakeRefusals();
  // The frames whose drop notices arrived since the last call (a notice of this run and configuration; its
  // frame counts as done, so later parts of it are duplicates).
  std::vector<std::int64_t> TakeDropped();
  const Counters& counters() const { return counters_; }
  size_t pending_frames() const { return pending_.size(); }

 private:
  struct Pending {
    semap_lcm::depth_frame_part_t header;  // the first part received, without its payload
    DepthFrameMessage frame;               // planes allocated at the first part, filled band by band
    std::vector<bool> got;                 // per part
    std::vector<bool> rows;                // per image row: covered by a part received
    int parts_received = 0;
  };
  struct DCtxFree {
    void operator()(ZSTD_DCtx_s* d) const;
  };

  bool Admit(const semap_lcm::depth_frame_part_t& part);
  void Refuse(const std::string& node, const std::string& reason);
  void GiveUp(std::map<std::int64_t, Pending>::iterator it);
  bool Decompress(const semap_lcm::depth_frame_part_t& part);
  std::optional<DepthFrameMessage> Place(semap_lcm::depth_frame_part_t part);

  std::int64_t run_id_;
  std::int64_t config_fingerprint_;
  size_t max_pending_frames_;
  std::optional<std::int64_t> calibration_fingerprint_;                     // of the first accepted frame
  std::int64_t floor_frame_id_ = std::numeric_limits<std::int64_t>::min();  // parts below are late
  std::map<std::int64_t, Pending> pending_;
  std::deque<std::int64_t> completed_;  // the latest completed frame ids (their parts are duplicates)
  std::set<std::string> refusals_seen_;
  std::vector<std::string> refusals_new_;
  std::vector<std::int64_t> dropped_;  // frames of the notices not taken yet
  std::vector<std::uint8_t> band_;     // decompressed band
  std::unique_ptr<ZSTD_DCtx_s, DCtxFree> dctx_;
  Counters counters_;
};

}  // namespace semap::io
