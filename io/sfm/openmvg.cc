#include "io/sfm/openmvg.h"

#include <unordered_set>

#include "io/sfm/internal/camera_models.h"
#include "io/sfm/internal/cereal_json.h"
#include "io/sfm/internal/json_fields.h"
#include "io/sfm/internal/sfm_checks.h"

namespace semap::io {

using namespace sfm_internal;

namespace {

// OpenMVG's UndefinedIndexT: a view without intrinsics or pose.
constexpr std::int64_t kUndefinedIndex = 4294967295;

struct PendingView {
  SfmView view;
  std::int64_t pose_id = kUndefinedIndex;
  EntryRef at;
};

// "<array>[i] (key K)" entries of a cereal map; `body` gets the entry's key and value.
template <typename Body>
void ForEachKeyed(const JsonObject& root, const char* array_name, EntryRef* at, Body body) {
  at->entry.clear();  // a missing array is the document's fault, not the last entry read before it
  const nlohmann::json& array = root.Array(array_name);
  for (std::size_t i = 0; i < array.size(); ++i) {
    at->entry = std::string(array_name) + "[" + std::to_string(i) + "]";
    const JsonObject entry(array[i], at);
    const std::int64_t key = entry.Int("key", 0, kUndefinedIndex - 1);
    at->entry += " (key " + std::to_string(key) + ")";
    body(key, entry.Object("value"));
  }
}

}  // namespace

SfmReconstruction ReadOpenMvgJson(const std::filesystem::path& path) {
  const nlohmann::json doc = ReadJsonFile(path);
  EntryRef at{path, ""};
  const JsonObject root(doc, &at);
  SfmReconstruction r;
  ReadVersionAndRoot(root, "sfm_data_version", &r);
  CerealReader cereal;

  // Views first (cereal numbers pointers in document order), resolved against poses below.
  std::vector<PendingView> pending;
  IdIndex all_views("view");
  ForEachKeyed(root, "views", &at, [&](std::int64_t key, const JsonObject& value) {
    all_views.Add(at, "key", key, static_cast<std::uint32_t>(pending.size()));
    cereal.PolymorphicName(value, "view");
    const JsonObject data = cereal.PointerData(value);
    PendingView p;
    p.at = at;
    p.view.id = key;
    p.view.name =
        (data.Has("local_path") ? data.String("local_path") : std::string()) + data.String("filename");
    const std::int64_t intrinsic = data.Int("id_intrinsic", 0, kUndefinedIndex);
    p.view.intrinsics_id = intrinsic == kUndefinedIndex ? kNoIntrinsics : intrinsic;
    p.pose_id = data.Int("id_pose", 0, kUndefinedIndex);
    pending.push_back(std::move(p));
  });

  IdIndex intrinsics("intrinsic");
  ForEachKeyed(root, "intrinsics", &at, [&](std::int64_t key, const JsonObject& value) {
    const std::string model = cereal.PolymorphicName(value);
    intrinsics.Add(at, "key", key, static_cast<std::uint32_t>(r.intrinsics.size()));
    r.intrinsics.push_back(ParseIntrinsicData(cereal.PointerData(value), model, key));
  });

  IdIndex poses("pose");
  std::vector<Pose3d> pose_values;
  ForEachKeyed(root, "extrinsics", &at, [&](std::int64_t key, const JsonObject& value) {
    poses.Add(at, "key", key, static_cast<std::uint32_t>(pose_values.size()));
    const Eigen::Matrix3d rotation = value.RowMatrix3("rotation");
    CheckRotation(at, value.Field("rotation"), rotation);
    pose_values.push_back(PoseFromRotationAndCenter(rotation, value.Vec3("center")));
  });

  // Posed views, in the file's order.
  IdIndex views("view");
  std::unordered_set<std::int64_t> unposed;
  for (PendingView& p : pending) {
    if (p.view.intrinsics_id != kNoIntrinsics) {
      intrinsics.Get(p.at, "value.ptr_wrapper.data.id_intrinsic", p.view.intrinsics_id);
    }
    const auto pose = p.pose_id == kUndefinedIndex ? std::nullopt : poses.Find(p.pose_id);
    if (!pose) {
      unposed.insert(p.view.id);
      continue;
    }
    p.view.world_from_cam = pose_values[*pose];
    views.Add(p.at, "key", p.view.id, static_cast<std::uint32_t>(r.views.size()));
    r.views.push_back(std::move(p.view));
  }

  AllOrNone labels("points");
  IdIndex points("point");
  ForEachKeyed(root, "structure", &at, [&](std::int64_t key, const JsonObject& value) {
    const auto point = static_cast<std::uint32_t>(r.num_points());
    points.Add(at, "key", key, point);
    r.point_ids.push_back(key);
    r.points_world.push_back(value.Vec3("X"));
    const bool has_label = value.Has("label");
    labels.Check(at, value.Field("label"), has_label);
    if (has_label) r.point_labels.push_back(static_cast<Label>(value.Int("label", 0, 255)));
    const nlohmann::json& observations = value.Array("observations");
    for (std::size_t k = 0; k < observations.size(); ++k) {
      const JsonObject o = ArrayObject(observations, k, &at, value.Field("observations"));
      const std::int64_t view_id = o.Int("key", 0, kUndefinedIndex);
      if (unposed.count(view_id)) at.Fail(o.Field("key"), "view " + std::to_string(view_id) + " has no pose");
      SfmObservation obs;
      obs.point = point;
      obs.view = views.Get(at, o.Field("key"), view_id);
      const JsonObject ov = o.Object("value");
      if (ov.Has("x")) obs.pixel_px = ov.Vec2("x");
      r.observations.push_back(obs);
    }
  });
  r.SortObservations();
  r.AssertConsistent();
  return r;
}

void WriteOpenMvgJson(const std::filesystem::path& path, const SfmReconstruction& r) {
  r.AssertConsistent();
  CerealWriter cereal;
  nlohmann::json views = nlohmann::json::array();
  for (const SfmView& v : r.views) {
    const SfmIntrinsics* k = r.FindIntrinsics(v.intrinsics_id);
    nlohmann::json data = {{"local_path", ""},
                           {"filename", v.name},
                           {"width", k ? k->width_px : 0},
                           {"height", k ? k->height_px : 0},
                           {"id_view", v.id},
                           {"id_intrinsic", k ? v.intrinsics_id : kUndefinedIndex},
                           {"id_pose", v.id}};
    views.push_back({{"key", v.id}, {"value", cereal.Pointer("", std::move(data))}});
  }
  nlohmann::json intrinsics = nlohmann::json::array();
  for (const SfmIntrinsics& raw : r.intrinsics) {
    const SfmIntrinsics k = AsOpenMvgModel(raw);
    intrinsics.push_back({{"key", k.id}, {"value", cereal.Pointer(k.model, IntrinsicDataJson(k))}});
  }
  nlohmann::json extrinsics = nlohmann::json::array();
  for (const SfmView& v : r.views) {
    const Eigen::Matrix3d R = v.world_from_cam.linear().transpose();
    const Eigen::Vector3d c = v.world_from_cam.translation();
    extrinsics.push_back(
        {{"key", v.id},
         {"value",
          {{"rotation",
            {{R(0, 0), R(0, 1), R(0, 2)}, {R(1, 0), R(1, 1), R(1, 2)}, {R(2, 0), R(2, 1), R(2, 2)}}},
           {"center", {c.x(), c.y(), c.z()}}}}});
  }
  // Observations are sorted by point: one pass. id_feat numbers each view's observations.
  std::vector<std::int64_t> next_feature(r.views.size(), 0);
  nlohmann::json structure = nlohmann::json::array();
  std::size_t o = 0;
  for (std::uint32_t p = 0; p < r.num_points(); ++p) {
    nlohmann::json observations = nlohmann::json::array();
    for (; o < r.observations.size() && r.observations[o].point == p; ++o) {
      const SfmObservation& obs = r.observations[o];
      nlohmann::json value = {{"id_feat", next_feature[obs.view]++}};
      if (obs.pixel_px.allFinite()) value["x"] = {obs.pixel_px.x(), obs.pixel_px.y()};
      observations.push_back({{"key", r.views[obs.view].id}, {"value", std::move(value)}});
    }
    const Eigen::Vector3d& X = r.points_world[p];
    nlohmann::json value = {{"X", {X.x(), X.y(), X.z()}}, {"observations", std::move(observations)}};
    if (!r.point_labels.empty()) value["label"] = r.point_labels[p];
    structure.push_back({{"key", r.point_ids[p]}, {"value", std::move(value)}});
  }
  nlohmann::json doc = {{"sfm_data_version", "0.3"},
                        {"root_path", r.image_root},
                        {"views", std::move(views)},
                        {"intrinsics", std::move(intrinsics)},
                        {"extrinsics", std::move(extrinsics)},
                        {"structure", std::move(structure)},
                        {"control_points", nlohmann::json::array()}};
  WriteJsonFile(path, doc);
}

}  // namespace semap::io
