// The cereal JSON conventions OpenMVG's sfm_data.json uses (and the SLAM JSON borrows for its intrinsics):
// polymorphic objects carry "polymorphic_id" (+ "polymorphic_name" the first time a type appears, with the
// id's top bit set), shared pointers a "ptr_wrapper" with an "id" (top bit set and "data" the first time
// the pointer appears; later occurrences repeat the id alone).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_map>

#include "io/sfm/internal/json_fields.h"
#include "io/sfm/sfm_reconstruction.h"

namespace semap::io::sfm_internal {

inline constexpr std::uint32_t kCerealNewId = 0x80000000u;  // top bit: first occurrence
inline constexpr std::uint32_t kCerealPlainPointer =
    0x40000000u;  // polymorphic_id of a non-polymorphic pointee

class CerealReader {
 public:
  // The type of a polymorphic `value`: its polymorphic_name, or the name an earlier polymorphic_id
  // introduced; `fallback` when the object has neither (nullptr: that is an error).
  std::string PolymorphicName(const JsonObject& value, const char* fallback = nullptr);
  // value.ptr_wrapper.data, or the data of the earlier pointer with the same id.
  JsonObject PointerData(const JsonObject& value);

 private:
  std::unordered_map<std::uint32_t, std::string> type_names_;
  std::unordered_map<std::uint32_t, const nlohmann::json*> pointers_;
};

// Numbers the polymorphic types and pointers of one archive being written.
class CerealWriter {
 public:
  // {"polymorphic_id": ..., ["polymorphic_name": type,] "ptr_wrapper": {"id": ..., "data": data}}; an empty
  // `type` writes the non-polymorphic id (views).
  nlohmann::json Pointer(const std::string& type, nlohmann::json data);

 private:
  std::unordered_map<std::string, std::uint32_t> type_ids_;
  std::uint32_t next_pointer_ = 1;
};

// An OpenMVG intrinsic's data object (width, height, focal_length, principal_point, distortion array) of
// type `model`. Unknown types keep their name and width/height, with no parameters.
SfmIntrinsics ParseIntrinsicData(const JsonObject& data, const std::string& model, std::int64_t id);
// The inverse; `k` must be in OpenMVG naming (AsOpenMvgModel).
nlohmann::json IntrinsicDataJson(const SfmIntrinsics& k);

}  // namespace semap::io::sfm_internal
