#include "engine/semantics/segmenter.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>
#include <vector>

#include "engine/core/check.h"
#include "tests/common/test_data.h"

namespace semap {
namespace {

constexpr const char* kEnetModel = "models/enet-cityscapes/enet-model.net";
constexpr const char* kKittiLeft = "data/kitti_stereo2015_subset/image_2/000002_10.png";

TEST(SemanticsOptions, ChecksFields) {
  EXPECT_NO_THROW(SemanticsOptions{}.Check());
  SemanticsOptions o;
  o.enet_input_width_px = 1001;
  EXPECT_THROW(o.Check(), InvalidOption);
  o = {};
  o.source = LabelSource::kEnet;
  o.enet_model_path.clear();
  EXPECT_THROW(o.Check(), InvalidOption);
  EXPECT_STREQ(LabelSourceName(LabelSource::kNone), "none");
}

TEST(FrameLabels, FollowsTheSource) {
  Frame f;
  f.id = 3;
  SemanticsOptions o;
  // auto without labels on disk: unlabelled; with: the disk labels.
  EXPECT_TRUE(FrameLabels(f, o, nullptr).empty());
  f.labels = cv::Mat(2, 2, CV_8UC1, cv::Scalar(5));
  EXPECT_EQ(FrameLabels(f, o, nullptr).at<Label>(0, 0), 5);
  o.source = LabelSource::kNone;
  EXPECT_TRUE(FrameLabels(f, o, nullptr).empty());
  o.source = LabelSource::kDisk;
  EXPECT_EQ(FrameLabels(f, o, nullptr).at<Label>(1, 1), 5);
  f.labels.release();
  try {
    FrameLabels(f, o, nullptr);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 3"), std::string::npos);
  }
  EXPECT_EQ(MakeSegmenter(o), nullptr);
}

TEST(EnetSegmenter, MissingModelIsAClearError) {
  SemanticsOptions o;
  o.source = LabelSource::kEnet;
  o.enet_model_path = (test::TempDir() / "nope.net").string();
  try {
    EnetSegmenter s(o);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nope.net"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos);
  }
}

TEST(EnetSegmenter, AFileThatIsNotANetworkIsAClearError) {
  SemanticsOptions o;
  o.source = LabelSource::kEnet;
  o.enet_model_path = (test::TempDir() / "garbage.net").string();
  {
    std::ofstream out(o.enet_model_path);
    out << "this is not a Torch7 network\n";
  }
  try {
    MakeSegmenter(o);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("garbage.net"), std::string::npos) << e.what();
  }
}

TEST(EnetSegmenter, ATruncatedModelIsAClearError) {
  SEMAP_REQUIRE_SHARED(kEnetModel);
  SemanticsOptions o;
  o.source = LabelSource::kEnet;
  o.enet_model_path = (test::TempDir() / "truncated.net").string();
  {
    std::ifstream in(test::SharedDir() / kEnetModel, std::ios::binary);
    std::vector<char> head(1 << 20);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream out(o.enet_model_path, std::ios::binary);
    out.write(head.data(), in.gcount());
  }
  try {
    EnetSegmenter s(o);
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("truncated.net"), std::string::npos) << e.what();
  }
}

TEST(EnetSegmenter, SegmentsARealKittiFrame) {
  SEMAP_REQUIRE_SHARED(kEnetModel);
  SEMAP_REQUIRE_SHARED(kKittiLeft);
  SemanticsOptions o;
  o.source = LabelSource::kEnet;
  o.enet_model_path = (test::SharedDir() / kEnetModel).string();
  auto segmenter = MakeSegmenter(o);
  ASSERT_NE(segmenter, nullptr);
  EXPECT_EQ(segmenter->name(), "enet-cityscapes");
  const cv::Mat image = cv::imread((test::SharedDir() / kKittiLeft).string(), cv::IMREAD_COLOR);
  const cv::Mat labels = segmenter->Segment(image);
  ASSERT_EQ(labels.size(), image.size());
  ASSERT_EQ(labels.type(), CV_8UC1);
  double max_id = 0;
  cv::minMaxLoc(labels, nullptr, &max_id);
  EXPECT_LT(max_id, 20);
  // ENet's quality on KITTI is moderate (much of the buildings comes out as "Train"; see
  // bench/results/depth.md), so this checks what it does reliably on this frame: road in the lower half,
  // several classes overall.
  const ClassMap& classes = segmenter->class_map();
  const cv::Mat lower = labels.rowRange(labels.rows / 2, labels.rows);
  const int road = cv::countNonZero(lower == classes.FindByName("Road"));
  EXPECT_GT(road, 0.05 * lower.total());
  std::set<Label> present(labels.begin<Label>(), labels.end<Label>());
  EXPECT_GE(present.size(), 5u);
  // Grey input works too; bad input is a clear error.
  cv::Mat grey;
  cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(segmenter->Segment(grey).size(), image.size());
  EXPECT_THROW(segmenter->Segment(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(segmenter->Segment(cv::Mat(4, 4, CV_32FC3)), std::invalid_argument);
}

// The fused head (the last layer computed here, on the image's rows only) against the whole network in
// OpenCV: the same labels but where float rounding breaks a near tie between two classes' scores.
TEST(EnetSegmenter, FusedHeadLabelsAsTheWholeNetwork) {
  SEMAP_REQUIRE_SHARED(kEnetModel);
  SEMAP_REQUIRE_SHARED(kKittiLeft);
  SemanticsOptions o;
  o.source = LabelSource::kEnet;
  o.enet_model_path = (test::SharedDir() / kEnetModel).string();
  EnetSegmenter fused(o, EnetHead::kFused);
  EnetSegmenter network(o, EnetHead::kNetwork);
  ASSERT_EQ(fused.head(), EnetHead::kFused) << "the model's last layer did not check out";
  ASSERT_EQ(network.head(), EnetHead::kNetwork);
  const cv::Mat image = cv::imread((test::SharedDir() / kKittiLeft).string(), cv::IMREAD_COLOR);
  for (const bool keep_aspect : {true, false}) {
    o.enet_keep_aspect = keep_aspect;
    EnetSegmenter a(o, EnetHead::kFused);
    EnetSegmenter b(o, EnetHead::kNetwork);
    const cv::Mat fused_labels = a.Segment(image);
    const cv::Mat network_labels = b.Segment(image);
    ASSERT_EQ(fused_labels.size(), network_labels.size());
    const int differ = cv::countNonZero(fused_labels != network_labels);
    EXPECT_LE(differ, static_cast<int>(1e-4 * image.total())) << "keep_aspect " << keep_aspect;
  }
}

}  // namespace
}  // namespace semap
