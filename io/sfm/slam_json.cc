#include "io/sfm/slam_json.h"

#include <stdexcept>

#include "io/sfm/internal/camera_models.h"
#include "io/sfm/internal/cereal_json.h"
#include "io/sfm/internal/json_fields.h"
#include "io/sfm/internal/sfm_checks.h"

namespace semap::io {

using namespace sfm_internal;

namespace {

void ReadIntrinsics(const nlohmann::json& array, const std::filesystem::path& path, SfmReconstruction* out,
                    IdIndex* index) {
  CerealReader cereal;
  EntryRef at{path, ""};
  for (std::size_t i = 0; i < array.size(); ++i) {
    at.entry = "intrinsics[" + std::to_string(i) + "]";
    const JsonObject entry(array[i], &at);
    const std::int64_t id = entry.Int("intrinsicId", 0, INT64_MAX);
    at.entry += " (intrinsicId " + std::to_string(id) + ")";
    const JsonObject value = entry.Object("value");
    const std::string model = cereal.PolymorphicName(value, "pinhole");
    index->Add(at, "intrinsicId", id, static_cast<std::uint32_t>(out->intrinsics.size()));
    out->intrinsics.push_back(ParseIntrinsicData(cereal.PointerData(value), model, id));
  }
}

}  // namespace

SfmReconstruction ReadSlamJson(const std::filesystem::path& path) {
  const nlohmann::json doc = ReadJsonFile(path);
  EntryRef at{path, ""};
  const JsonObject root(doc, &at);
  SfmReconstruction r;
  ReadVersionAndRoot(root, "slam_data_version", &r);
  IdIndex intrinsics("intrinsic");
  ReadIntrinsics(root.Array("intrinsics"), path, &r, &intrinsics);

  const nlohmann::json& views = root.Array("views");
  IdIndex view_index("view");
  IdIndex point_index("point");
  AllOrNone labels("observations");
  for (std::size_t i = 0; i < views.size(); ++i) {
    at.entry = "views[" + std::to_string(i) + "]";
    const JsonObject v(views[i], &at);
    SfmView view;
    view.id = v.Int("viewId", 0, INT64_MAX);
    at.entry += " (viewId " + std::to_string(view.id) + ")";
    view_index.Add(at, "viewId", view.id, static_cast<std::uint32_t>(r.views.size()));
    view.name = (v.Has("local_path") ? v.String("local_path") : std::string()) +
                (v.Has("filename") ? v.String("filename") : std::string());
    view.intrinsics_id = v.Int("id_intrinsic", 0, INT64_MAX);
    intrinsics.Get(at, "id_intrinsic", view.intrinsics_id);
    const JsonObject extrinsic = v.Object("extrinsic");
    const Eigen::Matrix3d rotation = extrinsic.RowMatrix3("rotation");
    CheckRotation(at, extrinsic.Field("rotation"), rotation);
    view.world_from_cam = PoseFromRotationAndCenter(rotation, extrinsic.Vec3("center"));
    const auto view_number = static_cast<std::uint32_t>(r.views.size());
    r.views.push_back(std::move(view));

    const nlohmann::json& observations = v.Array("observations");
    for (std::size_t k = 0; k < observations.size(); ++k) {
      const JsonObject o = ArrayObject(observations, k, &at, "observations");
      const std::int64_t point_id = o.Int("pointId", 0, INT64_MAX);
      const Eigen::Vector3d position = o.Vec3("X");
      const bool has_label = o.Has("label");
      labels.Check(at, o.Field("label"), has_label);
      std::uint32_t point = 0;
      if (const auto found = point_index.Find(point_id)) {
        point = *found;
        r.points_world[point] = position;
      } else {
        point = static_cast<std::uint32_t>(r.num_points());
        point_index.Add(at, o.Field("pointId"), point_id, point);
        r.point_ids.push_back(point_id);
        r.points_world.push_back(position);
        if (has_label) r.point_labels.push_back(0);
      }
      if (has_label) r.point_labels[point] = static_cast<Label>(o.Int("label", 0, 255));
      SfmObservation obs;
      obs.point = point;
      obs.view = view_number;
      if (o.Has("x")) obs.pixel_px = o.Vec2("x");
      r.observations.push_back(obs);
    }
  }
  r.SortObservations();
  r.AssertConsistent();
  return r;
}

void WriteSlamJson(const std::filesystem::path& path, const SfmReconstruction& r) {
  r.AssertConsistent();
  nlohmann::json doc;
  doc["slam_data_version"] = "0.3";
  doc["root_path"] = r.image_root;
  CerealWriter cereal;
  nlohmann::json intrinsics = nlohmann::json::array();
  for (const SfmIntrinsics& raw : r.intrinsics) {
    const SfmIntrinsics k = AsOpenMvgModel(raw);
    intrinsics.push_back({{"intrinsicId", k.id}, {"value", cereal.Pointer(k.model, IntrinsicDataJson(k))}});
  }
  doc["intrinsics"] = std::move(intrinsics);

  // Observations grouped by view, in point order within a view.
  std::vector<std::vector<std::uint32_t>> by_view(r.views.size());
  for (std::uint32_t i = 0; i < r.observations.size(); ++i) by_view[r.observations[i].view].push_back(i);
  nlohmann::json views = nlohmann::json::array();
  for (std::size_t v = 0; v < r.views.size(); ++v) {
    const SfmView& view = r.views[v];
    const SfmIntrinsics* k = r.FindIntrinsics(view.intrinsics_id);
    if (k == nullptr) {
      throw std::invalid_argument("view " + std::to_string(view.id) +
                                  " has no intrinsics: the SLAM JSON needs them");
    }
    const Eigen::Matrix3d R = view.world_from_cam.linear().transpose();
    const Eigen::Vector3d c = view.world_from_cam.translation();
    nlohmann::json observations = nlohmann::json::array();
    for (std::uint32_t i : by_view[v]) {
      const SfmObservation& o = r.observations[i];
      const Eigen::Vector3d& X = r.points_world[o.point];
      nlohmann::json obs = {{"pointId", r.point_ids[o.point]}, {"X", {X.x(), X.y(), X.z()}}};
      if (o.pixel_px.allFinite()) obs["x"] = {o.pixel_px.x(), o.pixel_px.y()};
      if (!r.point_labels.empty()) obs["label"] = r.point_labels[o.point];
      observations.push_back(std::move(obs));
    }
    views.push_back(
        {{"viewId", view.id},
         {"local_path", ""},
         {"filename", view.name},
         {"width", k->width_px},
         {"height", k->height_px},
         {"id_intrinsic", view.intrinsics_id},
         {"extrinsic",
          {{"rotation",
            {{R(0, 0), R(0, 1), R(0, 2)}, {R(1, 0), R(1, 1), R(1, 2)}, {R(2, 0), R(2, 1), R(2, 2)}}},
           {"center", {c.x(), c.y(), c.z()}}}},
         {"observations", std::move(observations)}});
  }
  doc["views"] = std::move(views);
  WriteJsonFile(path, doc);
}

}  // namespace semap::io
