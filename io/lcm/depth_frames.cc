#include "io/lcm/depth_frames.h"

#include <zstd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace semap::io {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the float planes travel little-endian as in memory");

// Encoded size of depth_frame_part_t without its arrays (see the .lcm file): type fingerprint, counts,
// version, checksum, run and fingerprints, frame, calibration, pose, offset, planes, part, shuffle flag.
constexpr std::int64_t kPartFixedBytes =
    8 + 2 * 4 + 4 + 8 + 3 * 8 + 8 + 2 * 8 + 2 * 8 + 5 * 8 + 2 * 4 + 1 + 12 * 8 + 2 * 8 + 1 + 1 + 4 * 4 + 1;
// Where the checksum sits in an encoded part: after the type fingerprint, the counts and the version.
constexpr size_t kChecksumOffset = 8 + 2 * 4 + 4;
constexpr size_t kChecksumBytes = 8;
constexpr int kMaxImageSidePx = 1 << 14;
constexpr size_t kMaxNameBytes = 255;
// Completed frame ids remembered, so that their late duplicates are not taken for new frames.
constexpr size_t kCompletedRemembered = 64;

// A 64-bit hash made of bijective steps only: for a fixed rest of the input, each step is a bijection of the
// word it takes and of the state it carries, so changing any single word (any bit) changes the result.
class Hash64 {
 public:
  explicit Hash64(std::uint64_t seed) : h_(seed) {}
  void Word(std::uint64_t w) {
    w *= 0x87c37b91114253d5ULL;
    w = std::rotl(w, 31);
    w *= 0x4cf5ad432745937fULL;
    h_ ^= w;
    h_ = std::rotl(h_, 27) * 5 + 0x52dce729ULL;
  }
  std::uint64_t Finish(std::uint64_t length) const {
    std::uint64_t z = h_ ^ length;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t h_;
};

// The checksum of an encoded part: every byte, the checksum field's read as zero.
std::uint64_t PartChecksum(const std::uint8_t* bytes, size_t size) {
  Hash64 hash(0x5e3a9d7f0c1b2e4dULL);
  for (size_t off = 0; off < size; off += 8) {
    std::uint8_t w[8] = {};
    std::memcpy(w, bytes + off, std::min<size_t>(8, size - off));
    for (size_t i = 0; i < 8; ++i) {
      if (off + i >= kChecksumOffset && off + i < kChecksumOffset + kChecksumBytes) w[i] = 0;
    }
    std::uint64_t word = 0;
    std::memcpy(&word, w, 8);
    hash.Word(word);
  }
  return hash.Finish(size);
}

// Big-endian, as LCM writes integers.
std::uint64_t ReadBigEndian(const std::uint8_t* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  return v;
}
void WriteBigEndian64(std::uint64_t v, std::uint8_t* p) {
  for (int i = 7; i >= 0; --i, v >>= 8) p[i] = static_cast<std::uint8_t>(v & 0xff);
}

std::string Hex(std::int64_t v) {
  char text[19];
  std::snprintf(text, sizeof text, "0x%016llx", static_cast<unsigned long long>(v));
  return text;
}

std::string SizeText(const cv::Mat& m) { return std::to_string(m.cols) + "x" + std::to_string(m.rows); }

// Bytes per pixel of a band: disparity and confidence, the label, the left image's channels.
size_t BytesPerPixel(int left_channels, bool has_labels) {
  return 2 * sizeof(float) + (has_labels ? 1 : 0) + static_cast<size_t>(left_channels);
}

void CheckFrame(const DepthFrameMessage& m) {
  auto fail = [](const std::string& field, const std::string& what) {
    throw std::invalid_argument(field + ": " + what);
  };
  if (m.left.empty() || (m.left.type() != CV_8UC1 && m.left.type() != CV_8UC3))
    fail("left", "must be a non-empty CV_8UC1 or CV_8UC3 image (got type " + std::to_string(m.left.type()) +
                     ", " + SizeText(m.left) + ")");
  if (m.left.cols > kMaxImageSidePx || m.left.rows > kMaxImageSidePx)
    fail("left",
         "must be at most " + std::to_string(kMaxImageSidePx) + " px a side (got " + SizeText(m.left) + ")");
  const std::string of_left = " of left's size " + SizeText(m.left);
  auto plane = [&](const cv::Mat& p, int type, const char* field, const char* type_name) {
    if (p.type() != type || p.size() != m.left.size())
      fail(field, std::string("must be ") + type_name + of_left + " (got type " + std::to_string(p.type()) +
                      ", " + SizeText(p) + ")");
  };
  plane(m.disparity_px, CV_32FC1, "disparity_px", "CV_32F");
  plane(m.confidence, CV_32FC1, "confidence", "CV_32F");
  if (!m.labels.empty()) plane(m.labels, CV_8UC1, "labels", "empty or CV_8UC1");
  if (m.calibration.width_px != m.left.cols || m.calibration.height_px != m.left.rows)
    fail("calibration", "image size " + std::to_string(m.calibration.width_px) + "x" +
                            std::to_string(m.calibration.height_px) + " must be left's " + SizeText(m.left));
  if (!m.calibration.IsValid())
    fail("calibration", "must be valid (finite, positive focal lengths and baseline)");
  if (m.world_from_cam && !m.world_from_cam->matrix().allFinite()) fail("world_from_cam", "must be finite");
  for (double v :
       {m.timestamp_s, m.sensed_unix_s, m.disparity_offset.constant_px, m.disparity_offset.per_row_px})
    if (!std::isfinite(v)) fail("timestamp_s/sensed_unix_s/disparity_offset", "must be finite");
}

// The header every part of the frame carries.
semap_lcm::depth_frame_part_t Header(const DepthFrameMessage& m) {
  semap_lcm::depth_frame_part_t h{};
  h.version = kDepthFrameFormatVersion;
  h.calibration_fingerprint = CalibrationFingerprint(m.calibration);
  h.frame_id = m.frame_id;
  h.timestamp_s = m.timestamp_s;
  h.sensed_unix_s = m.sensed_unix_s;
  h.first_frame_id = m.first_frame_id;
  h.sequence_frames = m.sequence_frames;
  h.fx_px = m.calibration.fx_px;
  h.fy_px = m.calibration.fy_px;
  h.cx_px = m.calibration.cx_px;
  h.cy_px = m.calibration.cy_px;
  h.baseline_m = m.calibration.baseline_m;
  h.width_px = m.calibration.width_px;
  h.height_px = m.calibration.height_px;
  h.has_pose = m.world_from_cam.has_value();
  if (m.world_from_cam) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) h.world_from_cam[4 * r + c] = m.world_from_cam->matrix()(r, c);
  }
  h.disparity_offset_constant_px = m.disparity_offset.constant_px;
  h.disparity_offset_per_row_px = m.disparity_offset.per_row_px;
  h.left_channels = static_cast<std::int8_t>(m.left.channels());
  h.has_labels = !m.labels.empty();
  return h;
}

// Appends a float plane's band, as is or byte-shuffled.
void AppendFloats(const cv::Mat& plane, int r0, int r1, bool shuffle, std::uint8_t* out) {
  const size_t width = static_cast<size_t>(plane.cols);
  const size_t n = width * static_cast<size_t>(r1 - r0);
  for (int r = r0; r < r1; ++r) {
    const auto* row = plane.ptr<std::uint8_t>(r);
    const size_t first = width * static_cast<size_t>(r - r0);
    if (!shuffle) {
      std::memcpy(out + 4 * first, row, 4 * width);
      continue;
    }
    for (size_t x = 0; x < width; ++x)
      for (size_t b = 0; b < 4; ++b) out[b * n + first + x] = row[4 * x + b];
  }
}

void ExtractFloats(const std::uint8_t* in, int r0, int r1, bool shuffled, cv::Mat* plane) {
  const size_t width = static_cast<size_t>(plane->cols);
  const size_t n = width * static_cast<size_t>(r1 - r0);
  for (int r = r0; r < r1; ++r) {
    auto* row = plane->ptr<std::uint8_t>(r);
    const size_t first = width * static_cast<size_t>(r - r0);
    if (!shuffled) {
      std::memcpy(row, in + 4 * first, 4 * width);
      continue;
    }
    for (size_t x = 0; x < width; ++x)
      for (size_t b = 0; b < 4; ++b) row[4 * x + b] = in[b * n + first + x];
  }
}

// Copies rows [r0, r1) of a plane of bytes to `out` (returns the end) or back.
std::uint8_t* AppendBytes(const cv::Mat& plane, int r0, int r1, std::uint8_t* out) {
  const size_t row_bytes = plane.elemSize() * static_cast<size_t>(plane.cols);
  for (int r = r0; r < r1; ++r, out += row_bytes) std::memcpy(out, plane.ptr(r), row_bytes);
  return out;
}
const std::uint8_t* ExtractBytes(const std::uint8_t* in, int r0, int r1, cv::Mat* plane) {
  const size_t row_bytes = plane->elemSize() * static_cast<size_t>(plane->cols);
  for (int r = r0; r < r1; ++r, in += row_bytes) std::memcpy(plane->ptr(r), in, row_bytes);
  return in;
}

// The uncompressed band [r0, r1) in the payload's layout (see depth_frame_part_t.lcm).
void BandBytes(const DepthFrameMessage& m, int r0, int r1, bool shuffle, std::vector<std::uint8_t>* out) {
  const size_t n = static_cast<size_t>(m.left.cols) * static_cast<size_t>(r1 - r0);
  out->resize(n * BytesPerPixel(m.left.channels(), !m.labels.empty()));
  std::uint8_t* p = out->data();
  AppendFloats(m.disparity_px, r0, r1, shuffle, p);
  AppendFloats(m.confidence, r0, r1, shuffle, p + 4 * n);
  p += 8 * n;
  if (!m.labels.empty()) p = AppendBytes(m.labels, r0, r1, p);
  AppendBytes(m.left, r0, r1, p);
}

struct CCtxFree {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};

struct Band {
  int row_begin = 0, row_end = 0;
  std::vector<std::uint8_t> payload;
};

// Cuts the frame into bands whose compressed payload fits `budget` bytes: each band starts from a row count
// scaled from the previous band's compressed size, and shrinks until it fits.
std::vector<Band> CompressBands(const DepthFrameMessage& m, const DepthFrameOptions& o, std::int64_t budget) {
  std::unique_ptr<ZSTD_CCtx, CCtxFree> cctx(ZSTD_createCCtx());
  if (!cctx) throw std::runtime_error("zstd: cannot create a compression context");
  const int height = m.left.rows;
  const std::int64_t row_bytes =
      static_cast<std::int64_t>(m.left.cols) *
      static_cast<std::int64_t>(BytesPerPixel(m.left.channels(), !m.labels.empty()));
  // Depth maps compress about 3:1; the first band's guess only sets how many tries it takes.
  int rows = static_cast<int>(std::clamp<std::int64_t>(3 * budget / row_bytes, 1, height));
  std::vector<Band> bands;
  std::vector<std::uint8_t> raw, packed;
  for (int r0 = 0; r0 < height;) {
    rows = std::min(rows, height - r0);
    BandBytes(m, r0, r0 + rows, o.byte_shuffle, &raw);
    packed.resize(ZSTD_compressBound(raw.size()));
    const size_t n =
        ZSTD_compressCCtx(cctx.get(), packed.data(), packed.size(), raw.data(), raw.size(), o.zstd_level);
    if (ZSTD_isError(n)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(n));
    const auto size = static_cast<std::int64_t>(n);
    if (size > budget) {
      if (rows == 1)
        throw std::invalid_argument("max_message_bytes: " + std::to_string(o.max_message_bytes) +
                                    " cannot hold one image row of " + std::to_string(m.left.cols) +
                                    " px (compressed " +
                                    std::to_string(size + (o.max_message_bytes - budget)) + " bytes)");
      rows =
          std::clamp(static_cast<int>(rows * 0.9 * static_cast<double>(budget) / static_cast<double>(size)),
                     1, rows - 1);
      continue;
    }
    bands.push_back({r0, r0 + rows, std::vector<std::uint8_t>(packed.begin(), packed.begin() + n)});
    r0 += rows;
    const double grow =
        0.92 * static_cast<double>(budget) / static_cast<double>(std::max<std::int64_t>(size, 1));
    rows = std::clamp(static_cast<int>(rows * grow), 1, std::max(1, 2 * rows));
  }
  return bands;
}

// True when two parts of one frame carry the same header (everything but the part, its rows and payload).
bool SameHeader(const semap_lcm::depth_frame_part_t& a, const semap_lcm::depth_frame_part_t& b) {
  return a.version == b.version && a.run_id == b.run_id && a.config_fingerprint == b.config_fingerprint &&
         a.calibration_fingerprint == b.calibration_fingerprint && a.frame_id == b.frame_id &&
         std::bit_cast<std::uint64_t>(a.timestamp_s) == std::bit_cast<std::uint64_t>(b.timestamp_s) &&
         std::bit_cast<std::uint64_t>(a.sensed_unix_s) == std::bit_cast<std::uint64_t>(b.sensed_unix_s) &&
         a.first_frame_id == b.first_frame_id && a.sequence_frames == b.sequence_frames &&
         a.fx_px == b.fx_px && a.fy_px == b.fy_px && a.cx_px == b.cx_px && a.cy_px == b.cy_px &&
         a.baseline_m == b.baseline_m && a.width_px == b.width_px && a.height_px == b.height_px &&
         a.has_pose == b.has_pose &&
         std::memcmp(a.world_from_cam, b.world_from_cam, sizeof a.world_from_cam) == 0 &&
         std::bit_cast<std::uint64_t>(a.disparity_offset_constant_px) ==
             std::bit_cast<std::uint64_t>(b.disparity_offset_constant_px) &&
         std::bit_cast<std::uint64_t>(a.disparity_offset_per_row_px) ==
             std::bit_cast<std::uint64_t>(b.disparity_offset_per_row_px) &&
         a.left_channels == b.left_channels && a.has_labels == b.has_labels && a.num_parts == b.num_parts &&
         a.node_name == b.node_name;
}

// The frame a header describes, its planes allocated (not yet filled).
DepthFrameMessage FrameOf(const semap_lcm::depth_frame_part_t& h) {
  DepthFrameMessage m;
  m.frame_id = h.frame_id;
  m.timestamp_s = h.timestamp_s;
  m.sensed_unix_s = h.sensed_unix_s;
  m.first_frame_id = h.first_frame_id;
  m.sequence_frames = h.sequence_frames;
  m.calibration = {h.fx_px, h.fy_px, h.cx_px, h.cy_px, h.baseline_m, h.width_px, h.height_px};
  if (h.has_pose) {
    Pose3d pose = Pose3d::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = h.world_from_cam[4 * r + c];
    m.world_from_cam = pose;
  }
  m.disparity_offset = {h.disparity_offset_constant_px, h.disparity_offset_per_row_px};
  m.left.create(h.height_px, h.width_px, CV_8UC(h.left_channels));
  m.disparity_px.create(h.height_px, h.width_px, CV_32FC1);
  m.confidence.create(h.height_px, h.width_px, CV_32FC1);
  if (h.has_labels) m.labels.create(h.height_px, h.width_px, CV_8UC1);
  return m;
}

// What is wrong with a decoded drop notice (num_parts 0), or empty: it carries no image, calibration or
// payload.
std::string NoticeError(const semap_lcm::depth_frame_part_t& m) {
  if (m.width_px != 0 || m.height_px != 0 || m.num_payload_bytes != 0 || m.part != 0 || m.row_begin != 0 ||
      m.row_end != 0 || m.left_channels != 0 || m.has_labels || m.has_pose)
    return "a drop notice with an image";
  if (m.calibration_fingerprint != CalibrationFingerprint(StereoCalibration{}))
    return "a drop notice's calibration";
  if (static_cast<size_t>(m.num_name_bytes) > kMaxNameBytes) return "node name too long";
  return {};
}

// What is wrong with a decoded part's header, or empty.
std::string HeaderError(const semap_lcm::depth_frame_part_t& m) {
  if (m.version != kDepthFrameFormatVersion)
    return "format version " + std::to_string(m.version) +
           " (this reader: " + std::to_string(kDepthFrameFormatVersion) + ")";
  if (m.num_parts == 0) return NoticeError(m);
  if (m.width_px < 1 || m.width_px > kMaxImageSidePx || m.height_px < 1 || m.height_px > kMaxImageSidePx)
    return "image size " + std::to_string(m.width_px) + "x" + std::to_string(m.height_px);
  const StereoCalibration c{m.fx_px, m.fy_px, m.cx_px, m.cy_px, m.baseline_m, m.width_px, m.height_px};
  if (CalibrationFingerprint(c) != m.calibration_fingerprint)
    return "calibration fingerprint of other fields";
  if (m.left_channels != 1 && m.left_channels != 3) return "left_channels " + std::to_string(m.left_channels);
  if (m.num_parts < 1 || m.num_parts > m.height_px || m.part < 0 || m.part >= m.num_parts)
    return "part " + std::to_string(m.part) + " of " + std::to_string(m.num_parts);
  if (m.row_begin < 0 || m.row_begin >= m.row_end || m.row_end > m.height_px)
    return "rows [" + std::to_string(m.row_begin) + ", " + std::to_string(m.row_end) + ") of " +
           std::to_string(m.height_px);
  for (double v : m.world_from_cam)
    if (!std::isfinite(v)) return "non-finite pose";
  if (static_cast<size_t>(m.num_name_bytes) > kMaxNameBytes) return "node name too long";
  return {};
}

}  // namespace

std::int64_t CalibrationFingerprint(const StereoCalibration& c) {
  Hash64 hash(0x3c6ef372fe94f82bULL);
  for (double v : {c.fx_px, c.fy_px, c.cx_px, c.cy_px, c.baseline_m})
    hash.Word(std::bit_cast<std::uint64_t>(v));
  hash.Word(static_cast<std::uint64_t>(static_cast<std::int64_t>(c.width_px)));
  hash.Word(static_cast<std::uint64_t>(static_cast<std::int64_t>(c.height_px)));
  return static_cast<std::int64_t>(hash.Finish(7));
}

std::int64_t DepthFramePartEncodedSize(std::int64_t name_bytes, std::int64_t payload_bytes) {
  return kPartFixedBytes + name_bytes + payload_bytes;
}

std::optional<semap_lcm::depth_frame_part_t> DecodeDepthFramePart(const void* data, size_t size,
                                                                  std::string* error) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  if (size < static_cast<size_t>(kPartFixedBytes)) {
    *error = "message of " + std::to_string(size) + " bytes is too short";
    return std::nullopt;
  }
  const auto name_bytes = static_cast<std::int32_t>(ReadBigEndian(bytes + 8, 4));
  const auto payload_bytes = static_cast<std::int32_t>(ReadBigEndian(bytes + 12, 4));
  if (name_bytes < 0 || payload_bytes < 0 ||
      DepthFramePartEncodedSize(name_bytes, payload_bytes) != static_cast<std::int64_t>(size)) {
    *error = "counts (" + std::to_string(name_bytes) + ", " + std::to_string(payload_bytes) +
             ") do not give the " + std::to_string(size) + " bytes of the message";
    return std::nullopt;
  }
  if (ReadBigEndian(bytes, 8) != static_cast<std::uint64_t>(semap_lcm::depth_frame_part_t::getHash())) {
    *error = "not a depth_frame_part_t (type fingerprint of another type or version)";
    return std::nullopt;
  }
  if (ReadBigEndian(bytes + kChecksumOffset, 8) != PartChecksum(bytes, size)) {
    *error = "checksum mismatch (damaged message)";
    return std::nullopt;
  }
  semap_lcm::depth_frame_part_t m;
  if (m.decode(data, 0, static_cast<int>(size)) != static_cast<int>(size)) {
    *error = "undecodable";
    return std::nullopt;
  }
  if (std::string bad = HeaderError(m); !bad.empty()) {
    *error = "frame " + std::to_string(m.frame_id) + " part " + std::to_string(m.part) + ": " + bad;
    return std::nullopt;
  }
  return m;
}

// ---------------------------------------------------------------------------------------------------------
// DepthFrameSender

DepthFrameSender::DepthFrameSender(const DepthFrameOptions& o, std::int64_t run_id,
                                   std::int64_t config_fingerprint, std::string node_name)
    : options_(o),
      run_id_(run_id),
      config_fingerprint_(config_fingerprint),
      node_name_(std::move(node_name)) {
  options_.Check();
  if (node_name_.size() > kMaxNameBytes)
    throw std::invalid_argument("node_name: must be at most " + std::to_string(kMaxNameBytes) +
                                " bytes (got " + std::to_string(node_name_.size()) + ")");
}

std::vector<EncodedMessage> DepthFrameSender::Encode(const DepthFrameMessage& m) const {
  CheckFrame(m);
  semap_lcm::depth_frame_part_t part = Header(m);
  part.run_id = run_id_;
  part.config_fingerprint = config_fingerprint_;
  part.node_name.assign(node_name_.begin(), node_name_.end());
  part.num_name_bytes = static_cast<std::int32_t>(part.node_name.size());
  part.byte_shuffled = options_.byte_shuffle;
  const std::int64_t budget = options_.max_message_bytes - DepthFramePartEncodedSize(part.num_name_bytes, 0);
  if (budget < 1)
    throw std::invalid_argument("max_message_bytes: " + std::to_string(options_.max_message_bytes) +
                                " cannot hold a part's header");
  std::vector<Band> bands = CompressBands(m, options_, budget);
  part.num_parts = static_cast<std::int32_t>(bands.size());
  std::vector<EncodedMessage> out;
  out.reserve(bands.size());
  for (size_t i = 0; i < bands.size(); ++i) {
    part.part = static_cast<std::int32_t>(i);
    part.row_begin = bands[i].row_begin;
    part.row_end = bands[i].row_end;
    part.payload = std::move(bands[i].payload);
    part.num_payload_bytes = static_cast<std::int32_t>(part.payload.size());
    EncodedMessage bytes(static_cast<size_t>(part.getEncodedSize()));
    part.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    WriteBigEndian64(PartChecksum(bytes.data(), bytes.size()), bytes.data() + kChecksumOffset);
    out.push_back(std::move(bytes));
  }
  return out;
}

EncodedMessage DepthFrameSender::EncodeDropped(std::int64_t frame_id, double timestamp_s,
                                               std::int64_t first_frame_id,
                                               std::int64_t sequence_frames) const {
  semap_lcm::depth_frame_part_t part{};
  part.version = kDepthFrameFormatVersion;
  part.run_id = run_id_;
  part.config_fingerprint = config_fingerprint_;
  part.calibration_fingerprint = CalibrationFingerprint(StereoCalibration{});
  part.frame_id = frame_id;
  part.timestamp_s = std::isfinite(timestamp_s) ? timestamp_s : 0.0;
  part.first_frame_id = first_frame_id;
  part.sequence_frames = sequence_frames;
  part.num_parts = 0;  // a notice: the frame will not come
  part.node_name.assign(node_name_.begin(), node_name_.end());
  part.num_name_bytes = static_cast<std::int32_t>(part.node_name.size());
  EncodedMessage bytes(static_cast<size_t>(part.getEncodedSize()));
  part.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  WriteBigEndian64(PartChecksum(bytes.data(), bytes.size()), bytes.data() + kChecksumOffset);
  return bytes;
}

// ---------------------------------------------------------------------------------------------------------
// DepthFrameAssembler

void DepthFrameAssembler::DCtxFree::operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }

DepthFrameAssembler::DepthFrameAssembler(std::int64_t run_id, std::int64_t config_fingerprint,
                                         int max_pending_frames)
    : run_id_(run_id),
      config_fingerprint_(config_fingerprint),
      max_pending_frames_(static_cast<size_t>(std::max(1, max_pending_frames))),
      dctx_(ZSTD_createDCtx()) {
  if (max_pending_frames < 1)
    throw std::invalid_argument("max_pending_frames: must be >= 1 (got " +
                                std::to_string(max_pending_frames) + ")");
  if (!dctx_) throw std::runtime_error("zstd: cannot create a decompression context");
}

DepthFrameAssembler::~DepthFrameAssembler() = default;

void DepthFrameAssembler::Refuse(const std::string& node, const std::string& reason) {
  ++counters_.refused;
  std::string line = "node " + node + ": " + reason;
  if (refusals_seen_.insert(line).second) refusals_new_.push_back(std::move(line));
}

std::vector<std::string> DepthFrameAssembler::TakeRefusals() { return std::exchange(refusals_new_, {}); }

std::vector<std::int64_t> DepthFrameAssembler::TakeDropped() { return std::exchange(dropped_, {}); }

// Run, configuration and calibration: whether a decoded part belongs to what this map node assembles.
bool DepthFrameAssembler::Admit(const semap_lcm::depth_frame_part_t& part) {
  if (part.run_id != run_id_) {
    ++counters_.foreign_run;
    return false;
  }
  const std::string node(part.node_name.begin(), part.node_name.end());
  if (part.config_fingerprint != config_fingerprint_) {
    Refuse(node, "config fingerprint " + Hex(part.config_fingerprint) + " differs from the map node's " +
                     Hex(config_fingerprint_));
    return false;
  }
  if (part.num_parts > 0 && calibration_fingerprint_ &&
      part.calibration_fingerprint != *calibration_fingerprint_) {
    Refuse(node, "calibration fingerprint " + Hex(part.calibration_fingerprint) +
                     " differs from the run's first frame's " + Hex(*calibration_fingerprint_));
    return false;
  }
  return true;
}

void DepthFrameAssembler::GiveUp(std::map<std::int64_t, Pending>::iterator it) {
  ++counters_.given_up;
  pending_.erase(it);
}

// Decompresses the part's payload into band_, after checking the zstd frame's declared size against the
// band's.
bool DepthFrameAssembler::Decompress(const semap_lcm::depth_frame_part_t& part) {
  const size_t expected = static_cast<size_t>(part.width_px) *
                          static_cast<size_t>(part.row_end - part.row_begin) *
                          BytesPerPixel(part.left_channels, part.has_labels);
  const void* src = part.payload.data();
  const size_t src_size = part.payload.size();
  if (ZSTD_getFrameContentSize(src, src_size) != expected ||
      ZSTD_findFrameCompressedSize(src, src_size) != src_size)
    return false;
  band_.resize(expected);
  const size_t n = ZSTD_decompressDCtx(dctx_.get(), band_.data(), band_.size(), src, src_size);
  return !ZSTD_isError(n) && n == expected;
}

std::optional<DepthFrameMessage> DepthFrameAssembler::Add(const void* data, size_t size) {
  std::string error;
  auto part = DecodeDepthFramePart(data, size, &error);
  if (!part) {
    ++counters_.malformed;
    return std::nullopt;
  }
  if (!Admit(*part)) return std::nullopt;
  if (part->frame_id < floor_frame_id_) {
    ++counters_.late;
    return std::nullopt;
  }
  if (std::find(completed_.begin(), completed_.end(), part->frame_id) != completed_.end()) {
    ++counters_.duplicates;
    return std::nullopt;
  }
  if (part->num_parts == 0) {
    // The node will not send this frame: whatever arrived of it is given up.
    ++counters_.notices;
    if (auto it = pending_.find(part->frame_id); it != pending_.end()) GiveUp(it);
    dropped_.push_back(part->frame_id);
    completed_.push_back(part->frame_id);
    if (completed_.size() > kCompletedRemembered) completed_.pop_front();
    return std::nullopt;
  }
  return Place(std::move(*part));
}

// Writes an admitted part's band into its frame (started at its first part); returns the frame when complete.
std::optional<DepthFrameMessage> DepthFrameAssembler::Place(semap_lcm::depth_frame_part_t part) {
  auto it = pending_.find(part.frame_id);
  if (it != pending_.end()) {
    Pending& p = it->second;
    if (!SameHeader(p.header, part)) {
      ++counters_.malformed;
      return std::nullopt;
    }
    if (p.got[static_cast<size_t>(part.part)]) {
      ++counters_.duplicates;
      return std::nullopt;
    }
    if (std::any_of(p.rows.begin() + part.row_begin, p.rows.begin() + part.row_end,
                    [](bool r) { return r; })) {
      ++counters_.malformed;  // rows another part of the frame already covers
      return std::nullopt;
    }
  }
  if (!Decompress(part)) {
    ++counters_.malformed;
    return std::nullopt;
  }
  if (it == pending_.end()) {
    // Beyond the bound, the oldest frame is given up: this one when it is older than every frame held.
    if (pending_.size() >= max_pending_frames_ && part.frame_id < pending_.begin()->first) {
      ++counters_.late;
      return std::nullopt;
    }
    while (pending_.size() >= max_pending_frames_) {
      floor_frame_id_ = std::max(floor_frame_id_, pending_.begin()->first + 1);
      GiveUp(pending_.begin());
    }
    Pending p;
    p.frame = FrameOf(part);
    p.got.assign(static_cast<size_t>(part.num_parts), false);
    p.rows.assign(static_cast<size_t>(part.height_px), false);
    p.header = part;
    p.header.payload.clear();
    p.header.num_payload_bytes = 0;
    it = pending_.emplace(part.frame_id, std::move(p)).first;
  }
  if (!calibration_fingerprint_) calibration_fingerprint_ = part.calibration_fingerprint;
  Pending& p = it->second;
  DepthFrameMessage& f = p.frame;
  const std::uint8_t* in = band_.data();
  const size_t n = static_cast<size_t>(part.width_px) * static_cast<size_t>(part.row_end - part.row_begin);
  ExtractFloats(in, part.row_begin, part.row_end, part.byte_shuffled, &f.disparity_px);
  ExtractFloats(in + 4 * n, part.row_begin, part.row_end, part.byte_shuffled, &f.confidence);
  in += 8 * n;
  if (part.has_labels) in = ExtractBytes(in, part.row_begin, part.row_end, &f.labels);
  ExtractBytes(in, part.row_begin, part.row_end, &f.left);
  p.got[static_cast<size_t>(part.part)] = true;
  std::fill(p.rows.begin() + part.row_begin, p.rows.begin() + part.row_end, true);
  ++counters_.parts;
  if (++p.parts_received < part.num_parts) return std::nullopt;
  std::optional<DepthFrameMessage> done;
  if (std::all_of(p.rows.begin(), p.rows.end(), [](bool r) { return r; })) {
    done = std::move(p.frame);
    ++counters_.frames;
  } else {
    ++counters_.malformed;  // every part arrived and rows are missing: the parts' ranges lie
  }
  pending_.erase(it);
  completed_.push_back(part.frame_id);
  if (completed_.size() > kCompletedRemembered) completed_.pop_front();
  return done;
}

std::vector<std::int64_t> DepthFrameAssembler::DropBefore(std::int64_t frame_id) {
  std::vector<std::int64_t> ids;
  floor_frame_id_ = std::max(floor_frame_id_, frame_id);
  while (!pending_.empty() && pending_.begin()->first < frame_id) {
    ids.push_back(pending_.begin()->first);
    GiveUp(pending_.begin());
  }
  return ids;
}

}  // namespace semap::io
