#include "io/lcm/depth_frames.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <thread>

namespace semap::io {
namespace {

constexpr std::int64_t kRun = 0x1234abcd;
constexpr std::int64_t kConfig = 0x0c0ffee;

StereoCalibration Calibration(int width, int height) {
  return {700.25, 701.5, width / 2.0 + 0.3, height / 2.0 - 0.7, 0.537, width, height};
}

struct FrameShape {
  int channels = 3;
  bool labels = true;
  bool pose = true;
};

// A frame of random planes, with smooth parts (as depth maps have) and odd floats (-0, denormals, NaN)
// that only a bit-exact transport keeps.
DepthFrameMessage RandomFrame(std::mt19937* rng, std::int64_t id, FrameShape shape, int width = 160,
                              int height = 90) {
  DepthFrameMessage m;
  m.frame_id = id;
  m.timestamp_s = 0.1 * static_cast<double>(id) + 1e-9;
  m.sensed_unix_s = 1.7e9 + 0.1 * static_cast<double>(id);
  m.first_frame_id = 3;
  m.sequence_frames = 271;
  m.calibration = Calibration(width, height);
  if (shape.pose) {
    Pose3d pose = Pose3d::Identity();
    pose.rotate(
        Eigen::AngleAxisd(0.3 + 0.01 * static_cast<double>(id), Eigen::Vector3d(0.2, 1, 0.1).normalized()));
    pose.pretranslate(Eigen::Vector3d(1.5, -0.25, 3.0 * static_cast<double>(id)));
    m.world_from_cam = pose;
  }
  m.disparity_offset = {0.125, -0.03125};
  std::uniform_real_distribution<float> u(0.f, 90.f);
  m.left.create(height, width, CV_8UC(shape.channels));
  m.disparity_px.create(height, width, CV_32FC1);
  m.confidence.create(height, width, CV_32FC1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const bool smooth = (x / 16 + y / 8) % 2 == 0;
      m.disparity_px.at<float>(y, x) = smooth ? 40.f - 0.25f * static_cast<float>(y) : u(*rng);
      m.confidence.at<float>(y, x) = smooth ? 1.f : u(*rng) / 90.f;
    }
  }
  m.disparity_px.at<float>(0, 0) = -0.f;
  m.disparity_px.at<float>(1, 1) = std::numeric_limits<float>::denorm_min();
  m.confidence.at<float>(2, 2) = std::numeric_limits<float>::quiet_NaN();
  cv::theRNG().state = (*rng)();
  cv::randu(m.left, cv::Scalar::all(0), cv::Scalar::all(256));
  if (shape.labels) {
    m.labels.create(height, width, CV_8UC1);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        m.labels.at<uchar>(y, x) = static_cast<uchar>((x / 20 + 3 * (y / 15)) % 19);
  }
  return m;
}

bool SameBytes(const cv::Mat& a, const cv::Mat& b) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  if (a.type() != b.type() || a.size() != b.size()) return false;
  for (int y = 0; y < a.rows; ++y) {
    if (std::memcmp(a.ptr(y), b.ptr(y), a.elemSize() * static_cast<size_t>(a.cols)) != 0) return false;
  }
  return true;
}

void ExpectSameFrame(const DepthFrameMessage& want, const DepthFrameMessage& got) {
  EXPECT_EQ(want.frame_id, got.frame_id);
  EXPECT_EQ(want.timestamp_s, got.timestamp_s);
  EXPECT_EQ(want.sensed_unix_s, got.sensed_unix_s);
  EXPECT_EQ(want.first_frame_id, got.first_frame_id);
  EXPECT_EQ(want.sequence_frames, got.sequence_frames);
  EXPECT_EQ(CalibrationFingerprint(want.calibration), CalibrationFingerprint(got.calibration));
  EXPECT_EQ(want.calibration.fx_px, got.calibration.fx_px);
  EXPECT_EQ(want.calibration.height_px, got.calibration.height_px);
  ASSERT_EQ(want.world_from_cam.has_value(), got.world_from_cam.has_value());
  if (want.world_from_cam) {
    EXPECT_TRUE(want.world_from_cam->matrix() == got.world_from_cam->matrix());
  }
  EXPECT_EQ(want.disparity_offset.constant_px, got.disparity_offset.constant_px);
  EXPECT_EQ(want.disparity_offset.per_row_px, got.disparity_offset.per_row_px);
  EXPECT_TRUE(SameBytes(want.left, got.left)) << "left";
  EXPECT_TRUE(SameBytes(want.disparity_px, got.disparity_px)) << "disparity_px";
  EXPECT_TRUE(SameBytes(want.confidence, got.confidence)) << "confidence";
  EXPECT_TRUE(SameBytes(want.labels, got.labels)) << "labels";
}

DepthFrameOptions SmallMessages(bool shuffle = true) {
  DepthFrameOptions o;
  o.max_message_bytes = 8000;
  o.byte_shuffle = shuffle;
  return o;
}

// Feeds every part; returns the frames completed.
std::vector<DepthFrameMessage> Feed(const std::vector<EncodedMessage>& parts, DepthFrameAssembler* a) {
  std::vector<DepthFrameMessage> out;
  for (const auto& p : parts) {
    if (auto f = a->Add(p.data(), p.size())) out.push_back(std::move(*f));
  }
  return out;
}

TEST(DepthFrames, EncodedSizeMatchesTheGeneratedCode) {
  semap_lcm::depth_frame_part_t m{};
  m.num_name_bytes = 5;
  m.node_name.assign(5, 'a');
  m.num_payload_bytes = 321;
  m.payload.assign(321, 7);
  EXPECT_EQ(DepthFramePartEncodedSize(5, 321), m.getEncodedSize());
}

TEST(DepthFrames, RoundTripIsBitExactInEveryShape) {
  std::mt19937 rng(7);
  std::int64_t id = 10;
  for (int channels : {1, 3}) {
    for (bool labels : {false, true}) {
      for (bool pose : {false, true}) {
        for (bool shuffle : {false, true}) {
          SCOPED_TRACE(testing::Message() << "channels " << channels << " labels " << labels << " pose "
                                          << pose << " shuffle " << shuffle);
          const DepthFrameMessage frame = RandomFrame(&rng, ++id, {channels, labels, pose});
          DepthFrameSender sender(SmallMessages(shuffle), kRun, kConfig, "cam-a");
          const auto parts = sender.Encode(frame);
          ASSERT_GT(parts.size(), 3u);
          for (const auto& p : parts) EXPECT_LE(p.size(), 8000u);
          DepthFrameAssembler assembler(kRun, kConfig);
          for (size_t i = 0; i + 1 < parts.size(); ++i)
            EXPECT_FALSE(assembler.Add(parts[i].data(), parts[i].size()).has_value()) << "part " << i;
          auto got = assembler.Add(parts.back().data(), parts.back().size());
          ASSERT_TRUE(got.has_value());
          ExpectSameFrame(frame, *got);
          EXPECT_EQ(assembler.counters().frames, 1);
          EXPECT_EQ(assembler.counters().parts, static_cast<std::int64_t>(parts.size()));
          EXPECT_EQ(assembler.counters().malformed, 0);
          EXPECT_EQ(assembler.pending_frames(), 0u);
        }
      }
    }
  }
}

TEST(DepthFrames, EveryPartFitsAnyBound) {
  std::mt19937 rng(8);
  const DepthFrameMessage frame = RandomFrame(&rng, 1, {}, 640, 200);
  for (int max_bytes : {6000, 9000, 60000, 65000, 1 << 22}) {
    DepthFrameOptions o;
    o.max_message_bytes = max_bytes;
    const auto parts = DepthFrameSender(o, kRun, kConfig, "n").Encode(frame);
    for (const auto& p : parts) EXPECT_LE(p.size(), static_cast<size_t>(max_bytes)) << max_bytes;
    DepthFrameAssembler assembler(kRun, kConfig);
    auto got = Feed(parts, &assembler);
    ASSERT_EQ(got.size(), 1u) << max_bytes;
    ExpectSameFrame(frame, got[0]);
  }
}

TEST(DepthFrames, ContiguityOfTheInputDoesNotMatter) {
  std::mt19937 rng(9);
  const DepthFrameMessage big = RandomFrame(&rng, 4, {}, 200, 100);
  DepthFrameMessage view = big;  // a region of interest: rows are not contiguous
  const cv::Rect roi(10, 5, 150, 80);
  view.left = big.left(roi);
  view.disparity_px = big.disparity_px(roi);
  view.confidence = big.confidence(roi);
  view.labels = big.labels(roi);
  view.calibration = Calibration(150, 80);
  DepthFrameAssembler assembler(kRun, kConfig);
  auto got = Feed(DepthFrameSender(SmallMessages(), kRun, kConfig, "n").Encode(view), &assembler);
  ASSERT_EQ(got.size(), 1u);
  ExpectSameFrame(view, got[0]);
}

TEST(DepthFrames, AnyOrderAndDuplicates) {
  std::mt19937 rng(11);
  const DepthFrameMessage frame = RandomFrame(&rng, 5, {});
  auto parts = DepthFrameSender(SmallMessages(), kRun, kConfig, "cam-a").Encode(frame);
  const size_t n = parts.size();
  for (size_t i = 0; i < n; i += 3) parts.push_back(parts[i]);
  std::shuffle(parts.begin(), parts.end(), rng);
  DepthFrameAssembler assembler(kRun, kConfig);
  auto got = Feed(parts, &assembler);
  ASSERT_EQ(got.size(), 1u);
  ExpectSameFrame(frame, got[0]);
  EXPECT_EQ(assembler.counters().parts, static_cast<std::int64_t>(n));
  EXPECT_EQ(assembler.counters().duplicates, static_cast<std::int64_t>(parts.size() - n));
  // A late duplicate of a completed frame does not start it again.
  EXPECT_FALSE(assembler.Add(parts[0].data(), parts[0].size()).has_value());
  EXPECT_EQ(assembler.pending_frames(), 0u);
  EXPECT_EQ(assembler.counters().frames, 1);
}

TEST(DepthFrames, InterleavedFramesComplete) {
  std::mt19937 rng(12);
  DepthFrameSender sender(SmallMessages(), kRun, kConfig, "cam-a");
  std::vector<DepthFrameMessage> frames;
  std::vector<EncodedMessage> all;
  for (int id = 0; id < 3; ++id) {
    frames.push_back(RandomFrame(&rng, id, {}));
    for (auto& p : sender.Encode(frames.back())) all.push_back(std::move(p));
  }
  std::shuffle(all.begin(), all.end(), rng);
  DepthFrameAssembler assembler(kRun, kConfig);
  auto got = Feed(all, &assembler);
  ASSERT_EQ(got.size(), 3u);
  for (const auto& g : got) ExpectSameFrame(frames[static_cast<size_t>(g.frame_id)], g);
}

TEST(DepthFrames, ALostPartLosesOnlyItsFrame) {
  std::mt19937 rng(13);
  DepthFrameSender sender(SmallMessages(), kRun, kConfig, "cam-a");
  auto first = sender.Encode(RandomFrame(&rng, 1, {}));
  const DepthFrameMessage second_frame = RandomFrame(&rng, 2, {});
  const auto second = sender.Encode(second_frame);
  const EncodedMessage lost = first[first.size() / 2];
  first.erase(first.begin() + static_cast<std::ptrdiff_t>(first.size() / 2));
  DepthFrameAssembler assembler(kRun, kConfig);
  EXPECT_TRUE(Feed(first, &assembler).empty());
  auto got = Feed(second, &assembler);
  ASSERT_EQ(got.size(), 1u);
  ExpectSameFrame(second_frame, got[0]);
  EXPECT_EQ(assembler.pending_frames(), 1u);
  EXPECT_EQ(assembler.DropBefore(2), std::vector<std::int64_t>{1});
  EXPECT_EQ(assembler.pending_frames(), 0u);
  EXPECT_EQ(assembler.counters().given_up, 1);
  // The lost part arriving after all completes nothing and holds nothing.
  EXPECT_FALSE(assembler.Add(lost.data(), lost.size()).has_value());
  EXPECT_EQ(assembler.pending_frames(), 0u);
  EXPECT_EQ(assembler.counters().late, 1);
  EXPECT_TRUE(assembler.DropBefore(100).empty());
}

TEST(DepthFrames, ForeignRunIsCounted) {
  std::mt19937 rng(14);
  const auto parts =
      DepthFrameSender(SmallMessages(), kRun + 1, kConfig, "cam-a").Encode(RandomFrame(&rng, 1, {}));
  DepthFrameAssembler assembler(kRun, kConfig);
  EXPECT_TRUE(Feed(parts, &assembler).empty());
  EXPECT_EQ(assembler.counters().foreign_run, static_cast<std::int64_t>(parts.size()));
  EXPECT_EQ(assembler.counters().parts, 0);
  EXPECT_EQ(assembler.pending_frames(), 0u);
  EXPECT_TRUE(assembler.TakeRefusals().empty());
}

// A drop notice: one small message that gives its frame up at once, ahead of any part of it; damaged, foreign
// or of another configuration, it is counted as any part would be.
TEST(DepthFrames, ADropNoticeGivesItsFrameUpAndIsCheckedLikeAPart) {
  std::mt19937 rng(21);
  const DepthFrameSender sender(SmallMessages(), kRun, kConfig, "cam-a");
  const EncodedMessage notice = sender.EncodeDropped(5, 0.5, 0, 20);
  EXPECT_EQ(static_cast<std::int64_t>(notice.size()), DepthFramePartEncodedSize(5, 0));  // no payload
  DepthFrameAssembler assembler(kRun, kConfig);
  const auto parts5 = sender.Encode(RandomFrame(&rng, 5, {}));
  ASSERT_GE(parts5.size(), 2u);
  EXPECT_FALSE(assembler.Add(parts5[0].data(), parts5[0].size()));  // a part of it is held...
  EXPECT_EQ(assembler.pending_frames(), 1u);
  EXPECT_FALSE(assembler.Add(notice.data(), notice.size()));  // ...and given up by the notice
  EXPECT_EQ(assembler.pending_frames(), 0u);
  EXPECT_EQ(assembler.TakeDropped(), (std::vector<std::int64_t>{5}));
  EXPECT_TRUE(assembler.TakeDropped().empty());
  EXPECT_EQ(assembler.counters().notices, 1);
  for (const auto& p : parts5) EXPECT_FALSE(assembler.Add(p.data(), p.size()));  // the rest: duplicates
  // Frame 6 still completes; a notice does not fix the run's calibration.
  EXPECT_EQ(Feed(sender.Encode(RandomFrame(&rng, 6, {})), &assembler).size(), 1u);
  EncodedMessage damaged = notice;
  damaged[damaged.size() / 2] ^= 0x10;
  EXPECT_FALSE(assembler.Add(damaged.data(), damaged.size()));
  EXPECT_EQ(assembler.counters().malformed, 1);
  const EncodedMessage foreign =
      DepthFrameSender(SmallMessages(), kRun + 1, kConfig, "x").EncodeDropped(7, 0, 0, 20);
  const EncodedMessage other =
      DepthFrameSender(SmallMessages(), kRun, kConfig + 1, "y").EncodeDropped(7, 0, 0, 20);
  assembler.Add(foreign.data(), foreign.size());
  assembler.Add(other.data(), other.size());
  EXPECT_EQ(assembler.counters().foreign_run, 1);
  EXPECT_EQ(assembler.counters().refused, 1);
  EXPECT_TRUE(assembler.TakeDropped().empty());
}

TEST(DepthFrames, AnotherConfigIsRefusedNamingTheNode) {
  std::mt19937 rng(15);
  DepthFrameSender sender(SmallMessages(), kRun, 0x77, "cam-a");
  const auto parts = sender.Encode(RandomFrame(&rng, 1, {}));
  DepthFrameAssembler assembler(kRun, kConfig);
  EXPECT_TRUE(Feed(parts, &assembler).empty());
  EXPECT_TRUE(Feed(sender.Encode(RandomFrame(&rng, 2, {})), &assembler).empty());
  EXPECT_GE(assembler.counters().refused, static_cast<std::int64_t>(parts.size()));
  const auto refusals = assembler.TakeRefusals();
  ASSERT_EQ(refusals.size(), 1u);
  EXPECT_NE(refusals[0].find("node cam-a"), std::string::npos) << refusals[0];
  EXPECT_NE(refusals[0].find("config fingerprint"), std::string::npos) << refusals[0];
  EXPECT_NE(refusals[0].find("0x0000000000000077"), std::string::npos) << refusals[0];
  EXPECT_NE(refusals[0].find("0x0000000000c0ffee"), std::string::npos) << refusals[0];
  EXPECT_TRUE(assembler.TakeRefusals().empty());
  EXPECT_EQ(assembler.counters().frames, 0);
}

TEST(DepthFrames, ACalibrationOtherThanTheFirstFramesIsRefused) {
  std::mt19937 rng(16);
  DepthFrameSender sender(SmallMessages(), kRun, kConfig, "cam-b");
  DepthFrameAssembler assembler(kRun, kConfig);
  ASSERT_EQ(Feed(sender.Encode(RandomFrame(&rng, 1, {})), &assembler).size(), 1u);
  DepthFrameMessage other = RandomFrame(&rng, 2, {});
  other.calibration.baseline_m += 1e-6;
  EXPECT_TRUE(Feed(sender.Encode(other), &assembler).empty());
  EXPECT_GT(assembler.counters().refused, 0);
  const auto refusals = assembler.TakeRefusals();
  ASSERT_EQ(refusals.size(), 1u);
  EXPECT_NE(refusals[0].find("node cam-b: calibration fingerprint"), std::string::npos) << refusals[0];
  // The first frame's calibration is still accepted.
  EXPECT_EQ(Feed(sender.Encode(RandomFrame(&rng, 3, {})), &assembler).size(), 1u);
}

TEST(DepthFrames, APartDisagreeingWithTheFramesFirstPartIsMalformed) {
  std::mt19937 rng(17);
  DepthFrameSender sender(SmallMessages(), kRun, kConfig, "cam-a");
  const DepthFrameMessage frame = RandomFrame(&rng, 1, {});
  DepthFrameMessage changed = frame;
  changed.timestamp_s += 0.5;
  const auto a = sender.Encode(frame);
  const auto b = sender.Encode(changed);
  ASSERT_EQ(a.size(), b.size());
  DepthFrameAssembler assembler(kRun, kConfig);
  EXPECT_FALSE(assembler.Add(a[0].data(), a[0].size()).has_value());
  for (size_t i = 1; i < b.size(); ++i) EXPECT_FALSE(assembler.Add(b[i].data(), b[i].size()).has_value());
  EXPECT_EQ(assembler.counters().malformed, static_cast<std::int64_t>(b.size() - 1));
  std::vector<EncodedMessage> rest(a.begin() + 1, a.end());
  auto got = Feed(rest, &assembler);
  ASSERT_EQ(got.size(), 1u);
  ExpectSameFrame(frame, got[0]);
}

TEST(DepthFrames, DamagedMessagesAreMalformedNeverACrash) {
  std::mt19937 rng(18);
  const DepthFrameMessage frame = RandomFrame(&rng, 1, {3, true, true});
  const auto parts = DepthFrameSender(SmallMessages(), kRun, kConfig, "cam-a").Encode(frame);
  DepthFrameAssembler assembler(kRun, kConfig);
  std::uniform_int_distribution<int> kind(0, 4);
  std::uniform_int_distribution<int> byte(0, 255);
  std::int64_t corrupted = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    EncodedMessage m = parts[static_cast<size_t>(trial) % parts.size()];
    std::uniform_int_distribution<size_t> at(0, m.size() - 1);
    switch (kind(rng)) {
      case 0:  // truncated
        m.resize(at(rng));
        break;
      case 1:  // one to three bits flipped
        for (int k = 0, flips = 1 + trial % 3; k < flips; ++k)
          m[at(rng)] ^= static_cast<std::uint8_t>(1u << (trial + k) % 8);
        break;
      case 2:  // random bytes of a random length
        m.resize(at(rng));
        for (auto& b : m) b = static_cast<std::uint8_t>(byte(rng));
        break;
      case 3:  // the right type fingerprint, then garbage
        for (size_t i = 8; i < m.size(); ++i) m[i] = static_cast<std::uint8_t>(byte(rng));
        break;
      default:  // a count claiming more than the message holds
        m[8 + 4 * (trial % 2)] ^= 0x40;
        break;
    }
    if (m == parts[static_cast<size_t>(trial) % parts.size()]) continue;
    ++corrupted;
    EXPECT_FALSE(assembler.Add(m.data(), m.size()).has_value());
  }
  EXPECT_EQ(assembler.counters().malformed, corrupted);
  EXPECT_EQ(assembler.counters().parts, 0);
  EXPECT_EQ(assembler.pending_frames(), 0u);
  auto got = Feed(parts, &assembler);
  ASSERT_EQ(got.size(), 1u);
  ExpectSameFrame(frame, got[0]);
}

TEST(DepthFrames, IncompleteFramesHeldAreBounded) {
  std::mt19937 rng(19);
  DepthFrameSender sender(SmallMessages(), kRun, kConfig, "cam-a");
  DepthFrameAssembler assembler(kRun, kConfig, 3);
  std::vector<EncodedMessage> last;
  for (int id = 0; id < 10; ++id) {
    last = sender.Encode(RandomFrame(&rng, id, {}));
    EXPECT_FALSE(assembler.Add(last[0].data(), last[0].size()).has_value());
    EXPECT_LE(assembler.pending_frames(), 3u);
  }
  EXPECT_EQ(assembler.pending_frames(), 3u);
  EXPECT_EQ(assembler.counters().given_up, 7);
  // The newest frames are the ones held: the last one completes.
  std::vector<EncodedMessage> rest(last.begin() + 1, last.end());
  EXPECT_EQ(Feed(rest, &assembler).size(), 1u);
  EXPECT_EQ(assembler.DropBefore(9), (std::vector<std::int64_t>{7, 8}));
}

TEST(DepthFrames, CalibrationFingerprintChangesWithEveryField) {
  const StereoCalibration c = Calibration(1241, 376);
  const std::int64_t base = CalibrationFingerprint(c);
  EXPECT_EQ(base, CalibrationFingerprint(Calibration(1241, 376)));
  std::vector<StereoCalibration> changed(7, c);
  changed[0].fx_px = std::nextafter(c.fx_px, 1e9);
  changed[1].fy_px = std::nextafter(c.fy_px, 0.0);
  changed[2].cx_px += 1.0;
  changed[3].cy_px = -c.cy_px;
  changed[4].baseline_m *= 2.0;
  changed[5].width_px += 1;
  changed[6].height_px -= 1;
  std::set<std::int64_t> seen{base};
  for (size_t i = 0; i < changed.size(); ++i) {
    const std::int64_t f = CalibrationFingerprint(changed[i]);
    EXPECT_NE(f, base) << "field " << i;
    EXPECT_TRUE(seen.insert(f).second) << "field " << i;
  }
  // Swapping two fields' values is a change too.
  StereoCalibration swapped = c;
  std::swap(swapped.fx_px, swapped.fy_px);
  EXPECT_NE(CalibrationFingerprint(swapped), base);
}

TEST(DepthFrames, BadInputIsRefusedNamingTheField) {
  std::mt19937 rng(20);
  DepthFrameSender sender(SmallMessages(), kRun, kConfig, "cam-a");
  auto expect_named = [&](DepthFrameMessage m, const std::string& field) {
    try {
      sender.Encode(m);
      ADD_FAILURE() << "no error for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  const DepthFrameMessage good = RandomFrame(&rng, 1, {});
  DepthFrameMessage m = good;
  m.disparity_px.convertTo(m.disparity_px, CV_64F);
  expect_named(m, "disparity_px");
  m = good;
  m.confidence = cv::Mat(10, 10, CV_32F, cv::Scalar(1));
  expect_named(m, "confidence");
  m = good;
  m.labels = cv::Mat(good.left.size(), CV_16U, cv::Scalar(1));
  expect_named(m, "labels");
  m = good;
  m.left = cv::Mat(good.left.size(), CV_8UC4, cv::Scalar(1));
  expect_named(m, "left");
  m = good;
  m.calibration.width_px += 2;
  expect_named(m, "calibration");

  DepthFrameOptions o;
  o.zstd_level = 40;
  EXPECT_THROW(DepthFrameSender(o, kRun, kConfig, "x"), InvalidOption);
  o = {};
  o.max_message_bytes = 1024;
  DepthFrameSender tiny(o, kRun, kConfig, "x");
  try {
    tiny.Encode(RandomFrame(&rng, 1, {}, 4000, 4));
    ADD_FAILURE() << "a row of 4000 random px fits 1024 bytes?";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_message_bytes"), std::string::npos) << e.what();
  }
}

TEST(DepthFrames, EncodeFromSeveralThreadsAtOnce) {
  std::mt19937 rng(21);
  const DepthFrameMessage frame = RandomFrame(&rng, 1, {});
  const DepthFrameSender sender(SmallMessages(), kRun, kConfig, "cam-a");
  const auto want = sender.Encode(frame);
  std::vector<std::vector<EncodedMessage>> got(4);
  std::vector<std::thread> threads;
  for (auto& g : got)
    threads.emplace_back([&] {
      for (int i = 0; i < 5; ++i) g = sender.Encode(frame);
    });
  for (auto& t : threads) t.join();
  for (const auto& g : got) EXPECT_EQ(g, want);
}

}  // namespace
}  // namespace semap::io
