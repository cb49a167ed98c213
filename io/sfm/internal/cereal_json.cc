#include "io/sfm/internal/cereal_json.h"

#include "io/sfm/internal/camera_models.h"

namespace semap::io::sfm_internal {

std::string CerealReader::PolymorphicName(const JsonObject& value, const char* fallback) {
  const bool has_id = value.Has("polymorphic_id");
  const std::uint32_t id =
      has_id ? static_cast<std::uint32_t>(value.Int("polymorphic_id", 0, UINT32_MAX)) : 0;
  if (value.Has("polymorphic_name")) {
    std::string name = value.String("polymorphic_name");
    if (has_id && (id & kCerealNewId)) type_names_[id & ~kCerealNewId] = name;
    return name;
  }
  if (has_id) {
    if (const auto it = type_names_.find(id & ~kCerealNewId); it != type_names_.end()) return it->second;
  }
  if (fallback != nullptr) return fallback;
  value.at().Fail(value.Field("polymorphic_id"),
                  has_id
                      ? "type id " + std::to_string(id) + " was not introduced by an earlier polymorphic_name"
                      : "missing (with no polymorphic_name)");
}

JsonObject CerealReader::PointerData(const JsonObject& value) {
  const JsonObject wrapper = value.Object("ptr_wrapper");
  const bool has_id = wrapper.Has("id");
  const std::uint32_t id = has_id ? static_cast<std::uint32_t>(wrapper.Int("id", 0, UINT32_MAX)) : 0;
  if (wrapper.Has("data")) {
    const nlohmann::json& data = wrapper.Get("data");
    if (has_id) pointers_[id & ~kCerealNewId] = &data;
    return wrapper.Object("data");
  }
  if (!has_id) wrapper.at().Fail(wrapper.Field("data"), "missing");
  const auto it = pointers_.find(id & ~kCerealNewId);
  if (it == pointers_.end()) {
    wrapper.at().Fail(wrapper.Field("id"), "pointer " + std::to_string(id) + " has no data here nor earlier");
  }
  return JsonObject(*it->second, &wrapper.at(), wrapper.Field("data") + ".");
}

nlohmann::json CerealWriter::Pointer(const std::string& type, nlohmann::json data) {
  nlohmann::json j;
  if (type.empty()) {
    j["polymorphic_id"] = kCerealPlainPointer;
  } else if (const auto it = type_ids_.find(type); it != type_ids_.end()) {
    j["polymorphic_id"] = it->second;
  } else {
    const auto id = static_cast<std::uint32_t>(type_ids_.size() + 1);
    type_ids_[type] = id;
    j["polymorphic_id"] = kCerealNewId | id;
    j["polymorphic_name"] = type;
  }
  j["ptr_wrapper"] = {{"id", kCerealNewId | next_pointer_++}, {"data", std::move(data)}};
  return j;
}

SfmIntrinsics ParseIntrinsicData(const JsonObject& data, const std::string& model, std::int64_t id) {
  SfmIntrinsics k;
  k.id = id;
  k.model = model;
  k.width_px = static_cast<int>(data.Int("width", 0, INT32_MAX));
  k.height_px = static_cast<int>(data.Int("height", 0, INT32_MAX));
  const auto m = OpenMvgModelByName(model);
  if (!m || m->distortion_size < 0) return k;
  k.params.push_back(data.Number("focal_length"));
  const Eigen::Vector2d pp = data.Vec2("principal_point");
  k.params.push_back(pp.x());
  k.params.push_back(pp.y());
  if (m->distortion_size > 0) {
    const std::vector<double> d = data.Numbers(m->distortion_field);
    if (d.size() != static_cast<std::size_t>(m->distortion_size)) {
      data.at().Fail(data.Field(m->distortion_field), "must have " + std::to_string(m->distortion_size) +
                                                          " numbers (got " + std::to_string(d.size()) + ")");
    }
    k.params.insert(k.params.end(), d.begin(), d.end());
  }
  return k;
}

nlohmann::json IntrinsicDataJson(const SfmIntrinsics& k) {
  nlohmann::json data;
  data["width"] = k.width_px;
  data["height"] = k.height_px;
  const auto m = OpenMvgModelByName(k.model);
  if (!m || m->distortion_size < 0 || k.params.size() < 3) return data;
  data["focal_length"] = k.params[0];
  data["principal_point"] = {k.params[1], k.params[2]};
  if (m->distortion_size > 0) {
    data[m->distortion_field] = std::vector<double>(k.params.begin() + 3, k.params.end());
  }
  return data;
}

}  // namespace semap::io::sfm_internal
