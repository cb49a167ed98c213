#include "engine/semantics/labelling.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/core/check.h"

namespace semap {
namespace {

std::string SizeText(cv::Size s) { return std::to_string(s.width) + "x" + std::to_string(s.height); }

}  // namespace

LabellingReport ApplyFirstCameraLabels(LabelledCloud& cloud, std::int64_t frame_id,
                                       const cv::Mat& label_image, cv::Size image_size, Label unlabelled_id,
                                       LabelSizePolicy policy) {
  SEMAP_ASSERT(cloud.pixels_px.size() == cloud.size(), "labelling needs the pixel of every point");
  SEMAP_ASSERT(cloud.camera_index.size() == cloud.size(), "labelling needs the camera of every point");
  SEMAP_ASSERT(cloud.camera_frame_ids.size() == cloud.camera_centers_world.size());
  LabellingReport report;
  cv::Mat labels = label_image;
  if (!labels.empty()) {
    if (labels.type() != CV_8UC1) {
      throw std::invalid_argument("label image of frame " + std::to_string(frame_id) +
                                  " must be 8-bit single channel (CV_8UC1), got type " +
                                  std::to_string(labels.type()));
    }
    if (labels.size() != image_size) {
      if (policy == LabelSizePolicy::kRefuse) {
        throw std::invalid_argument("label image of frame " + std::to_string(frame_id) + " is " +
                                    SizeText(labels.size()) + " but the image is " + SizeText(image_size));
      }
      cv::resize(label_image, labels, image_size, 0.0, 0.0, cv::INTER_NEAREST);
      report.resized = true;
    }
  }
  if (cloud.labels.empty()) cloud.labels.assign(cloud.size(), unlabelled_id);

  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.camera_frame_ids[cloud.camera_index[i]] != frame_id) {
      ++report.other_cameras;  // first observed elsewhere: that camera's label stands
      continue;
    }
    if (labels.empty()) {
      cloud.labels[i] = unlabelled_id;
      continue;
    }
    const long u = std::lround(cloud.pixels_px[i].x());
    const long v = std::lround(cloud.pixels_px[i].y());
    if (u < 0 || v < 0 || u >= labels.cols || v >= labels.rows) {
      cloud.labels[i] = unlabelled_id;
      ++report.outside_image;
      continue;
    }
    cloud.labels[i] = labels.at<std::uint8_t>(static_cast<int>(v), static_cast<int>(u));
    ++report.labelled;
  }
  return report;
}

std::optional<Label> SkyLabel(const ClassMap& class_map) {
  const int id = class_map.FindByName("sky");
  if (id < 0) return std::nullopt;
  return static_cast<Label>(id);
}

std::size_t RemoveLabel(LabelledCloud& cloud, Label label) {
  SEMAP_ASSERT(cloud.labels.size() == cloud.size(), "removing a label needs the label of every point");
  std::vector<std::uint32_t> keep;
  keep.reserve(cloud.size());
  for (std::uint32_t i = 0; i < cloud.size(); ++i) {
    if (cloud.labels[i] != label) keep.push_back(i);
  }
  const std::size_t removed = cloud.size() - keep.size();
  if (removed > 0) cloud = cloud.Subset(keep);
  return removed;
}

cv::Mat ColorizeLabels(const cv::Mat& label_image, const ClassMap& class_map) {
  if (label_image.type() != CV_8UC1) {
    throw std::invalid_argument("ColorizeLabels: label image must be CV_8UC1, got type " +
                                std::to_string(label_image.type()));
  }
  cv::Mat lut(1, 256, CV_8UC3);
  for (int id = 0; id < 256; ++id) {
    const auto rgb = class_map.Color(static_cast<Label>(id));
    lut.at<cv::Vec3b>(0, id) = cv::Vec3b(rgb[2], rgb[1], rgb[0]);
  }
  cv::Mat labels3, colour;
  cv::cvtColor(label_image, labels3, cv::COLOR_GRAY2BGR);
  cv::LUT(labels3, lut, colour);
  return colour;
}

cv::Mat OverlayLabels(const cv::Mat& image, const cv::Mat& label_image, const ClassMap& class_map,
                      double alpha) {
  if (image.size() != label_image.size()) {
    throw std::invalid_argument("OverlayLabels: image is " + SizeText(image.size()) + " but labels are " +
                                SizeText(label_image.size()));
  }
  cv::Mat bgr;
  if (image.channels() == 1) {
    cv::cvtColor(image, bgr, cv::COLOR_GRAY2BGR);
  } else {
    bgr = image;
  }
  cv::Mat out;
  cv::addWeighted(ColorizeLabels(label_image, class_map), alpha, bgr, 1.0 - alpha, 0.0, out);
  return out;
}

}  // namespace semap
