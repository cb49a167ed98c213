#include "io/lcm/mesh_blocks.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "io/lcm/lcm_codec.h"

namespace semap::io {
namespace {

// Encoded sizes (see the .lcm files): the fingerprint, the counts, the fixed fields, then per element.
constexpr std::int64_t kBlockFixedBytes = 8 + 3 * 4 + 3 * 8 + 3 * 4 + 4 + 4 + 4 + 4 + 1 + 4 + 4 + 4;
constexpr std::int64_t kBytesPerRemoved = 8;
constexpr std::int64_t kBytesPerVertex = 8 + 3 * 4 + 3 + 1;
constexpr std::int64_t kBytesPerTriangle = 8 + 3 * 4;
constexpr std::int64_t kEndFixedBytes = 8 + 4 + 3 * 8 + 4 * 4 + 8;
constexpr std::int64_t kBytesPerIndexEntry = 4 * 4 + 4 + 4;
// Rough whole-state bytes per triangle (its share of the vertices included), to choose delta or whole.
constexpr std::int64_t kWholeBytesPerTriangle = 36;
// Far more parts than a sane block has: a larger claim is a damaged message.
constexpr std::int32_t kMaxParts = 1 << 16;

template <typename Msg>
EncodedMessage Encode(const Msg& msg) {
  EncodedMessage out(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(out.data(), 0, static_cast<int>(out.size()));
  return out;
}

std::int32_t BigEndianInt32(const std::uint8_t* p) {
  return static_cast<std::int32_t>((std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) |
                                   (std::uint32_t(p[2]) << 8) | std::uint32_t(p[3]));
}

// Decodes `Msg` whose leading counts (right after the fingerprint) must give exactly `size` bytes.
template <typename Msg, typename SizeFn>
std::optional<Msg> CheckedDecode(const void* data, size_t size, int num_counts, SizeFn expected_size,
                                 std::string* error) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  if (size < static_cast<size_t>(8 + 4 * num_counts)) {
    *error = "message of " + std::to_string(size) + " bytes is too short";
    return std::nullopt;
  }
  std::array<std::int64_t, 3> counts{};
  for (int i = 0; i < num_counts; ++i) {
    counts[i] = BigEndianInt32(bytes + 8 + 4 * i);
    if (counts[i] < 0) {
      *error = "negative count " + std::to_string(counts[i]);
      return std::nullopt;
    }
  }
  const std::int64_t expected = expected_size(counts);
  if (expected != static_cast<std::int64_t>(size)) {
    *error = "counts (" + std::to_string(counts[0]) + ", " + std::to_string(counts[1]) + ", " +
             std::to_string(counts[2]) + ") need " + std::to_string(expected) + " bytes, the message has " +
             std::to_string(size);
    return std::nullopt;
  }
  Msg msg;
  if (msg.decode(data, 0, static_cast<int>(size)) != static_cast<int>(size)) {
    *error = "undecodable (wrong type fingerprint?)";
    return std::nullopt;
  }
  return msg;
}

}  // namespace

std::string BlockKey::ToString() const {
  return "(" + std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(z) + ")#" +
         std::to_string(serial);
}

std::int64_t MeshBlockEncodedSize(std::int64_t removed, std::int64_t vertices, std::int64_t triangles) {
  return kBlockFixedBytes + kBytesPerRemoved * removed + kBytesPerVertex * vertices +
         kBytesPerTriangle * triangles;
}

std::int64_t MeshEndEncodedSize(std::int64_t blocks) { return kEndFixedBytes + kBytesPerIndexEntry * blocks; }

std::optional<semap_lcm::mesh_block_t> DecodeMeshBlock(const void* data, size_t size, std::string* error) {
  auto msg = CheckedDecode<semap_lcm::mesh_block_t>(
      data, size, 3, [](const auto& c) { return MeshBlockEncodedSize(c[0], c[1], c[2]); }, error);
  if (!msg) return msg;
  const auto& m = *msg;
  std::string bad;
  if (m.version < 1) {
    bad = "version " + std::to_string(m.version) + " < 1";
  } else if (m.base_version < 0 || m.base_version >= m.version) {
    bad = "base_version " + std::to_string(m.base_version) + " not in [0, version " +
          std::to_string(m.version) + ")";
  } else if (m.num_parts < 1 || m.num_parts > kMaxParts || m.part < 0 || m.part >= m.num_parts) {
    bad = "part " + std::to_string(m.part) + " of " + std::to_string(m.num_parts);
  } else if (m.base_version > 0 && (m.num_parts != 1 || m.finalised)) {
    bad = "a delta in several parts or finalised";
  } else if (m.base_version == 0 && m.num_removed != 0) {
    bad = "a whole state with removals";
  } else if (m.block_triangles < m.num_triangles) {
    bad = "block_triangles " + std::to_string(m.block_triangles) + " < triangles carried " +
          std::to_string(m.num_triangles);
  }
  for (std::int32_t i = 0; bad.empty() && i < m.num_vertices; ++i) {
    for (float c : m.positions[i]) {
      if (!std::isfinite(c)) {
        bad = "vertex " + std::to_string(m.vertex_ids[i]) + " has a non-finite coordinate";
        break;
      }
    }
  }
  for (std::int32_t i = 0; bad.empty() && i < m.num_triangles; ++i) {
    for (auto v : m.triangles[i]) {
      if (v < 0 || v >= m.num_vertices) {
        bad = "triangle " + std::to_string(m.triangle_ids[i]) + " names vertex " + std::to_string(v) +
              " of the message's " + std::to_string(m.num_vertices);
        break;
      }
    }
  }
  if (!bad.empty()) {
    *error = "block (" + std::to_string(m.block[0]) + "," + std::to_string(m.block[1]) + "," +
             std::to_string(m.block[2]) + ")#" + std::to_string(m.serial) + ": " + bad;
    return std::nullopt;
  }
  return msg;
}

std::optional<semap_lcm::mesh_end_t> DecodeMeshEnd(const void* data, size_t size, std::string* error) {
  auto msg = CheckedDecode<semap_lcm::mesh_end_t>(
      data, size, 1, [](const auto& c) { return MeshEndEncodedSize(c[0]); }, error);
  if (!msg) return msg;
  if (msg->num_parts < 1 || msg->num_parts > kMaxParts || msg->part < 0 || msg->part >= msg->num_parts ||
      msg->total_blocks < msg->num_blocks || msg->rounds_left < -1) {
    *error = "index part " + std::to_string(msg->part) + " of " + std::to_string(msg->num_parts) + " with " +
             std::to_string(msg->num_blocks) + " of " + std::to_string(msg->total_blocks) +
             " blocks, rounds_left " + std::to_string(msg->rounds_left);
    return std::nullopt;
  }
  return msg;
}

// ---------------------------------------------------------------------------------------------------------
// MeshBlockSender

MeshBlockSender::MeshBlockSender(double block_size_m, int max_message_bytes, std::int64_t run_id)
    : block_size_m_(block_size_m), max_message_bytes_(max_message_bytes), run_id_(run_id) {}

BlockKey MeshBlockSender::CellOf(const Triangle& t) const {
  Eigen::Vector3f c = Eigen::Vector3f::Zero();
  for (auto v : t) c += vertices_.at(v).position;
  c /= 3.0f;
  const auto cell = [&](float x) {
    return static_cast<std::int32_t>(std::clamp(std::floor(double(x) / block_size_m_), -2.0e9, 2.0e9));
  };
  return {cell(c.x()), cell(c.y()), cell(c.z()), 0};
}

void MeshBlockSender::DropLive(LiveBlock& block, TriangleId id, const Triangle& t) {
  if (block.added.erase(id) == 0) block.removed.push_back(id);
  block.changed = true;
  for (auto v : t) {
    auto it = vertices_.find(v);
    if (it != vertices_.end() && --it->second.refs <= 0) vertices_.erase(it);
  }
  --live_triangles_;
}

semap_lcm::mesh_block_t MeshBlockSender::Header(const BlockKey& key, std::int32_t version) const {
  semap_lcm::mesh_block_t m{};
  m.utime = NowUtime();
  m.run_id = run_id_;
  m.frame_id = frame_id_;
  m.block[0] = key.x;
  m.block[1] = key.y;
  m.block[2] = key.z;
  m.serial = key.serial;
  m.block_size_m = static_cast<float>(block_size_m_);
  m.version = version;
  m.num_parts = 1;
  return m;
}

void MeshBlockSender::AddItem(semap_lcm::mesh_block_t* m, std::unordered_map<VertexId, std::int32_t>* local,
                              const Item& item) const {
  std::vector<std::int32_t> tri(3);
  for (int k = 0; k < 3; ++k) {
    const VertexId v = item.vertices[k];
    auto [it, inserted] = local->emplace(v, m->num_vertices);
    if (inserted) {
      const Vertex& vx = vertices_.at(v);
      m->vertex_ids.push_back(static_cast<std::int64_t>(v));
      m->positions.push_back({vx.position.x(), vx.position.y(), vx.position.z()});
      m->colors.push_back({vx.color[0], vx.color[1], vx.color[2]});
      m->labels.push_back(vx.label);
      ++m->num_vertices;
    }
    tri[k] = it->second;
  }
  m->triangle_ids.push_back(static_cast<std::int64_t>(item.id));
  m->triangles.push_back(std::move(tri));
  ++m->num_triangles;
}

std::vector<EncodedMessage> MeshBlockSender::EncodeWhole(const BlockKey& key, std::int32_t version,
                                                         bool finalised,
                                                         const std::vector<Item>& items) const {
  std::vector<semap_lcm::mesh_block_t> parts(1, Header(key, version));
  std::unordered_map<VertexId, std::int32_t> local;
  for (const Item& item : items) {
    auto& m = parts.back();
    std::int64_t new_vertices = 0;
    for (auto v : item.vertices) new_vertices += local.count(v) == 0 ? 1 : 0;
    if (m.num_triangles > 0 &&
        MeshBlockEncodedSize(0, m.num_vertices + new_vertices, m.num_triangles + 1) > max_message_bytes_) {
      parts.push_back(Header(key, version));
      local.clear();
    }
    AddItem(&parts.back(), &local, item);
  }
  std::vector<EncodedMessage> out;
  for (size_t i = 0; i < parts.size(); ++i) {
    parts[i].finalised = finalised;
    parts[i].part = static_cast<std::int32_t>(i);
    parts[i].num_parts = static_cast<std::int32_t>(parts.size());
    parts[i].block_triangles = static_cast<std::int32_t>(items.size());
    out.push_back(Encode(parts[i]));
  }
  return out;
}

std::optional<EncodedMessage> MeshBlockSender::EncodeDelta(const BlockKey& key, std::int32_t base,
                                                           std::int32_t version, std::int32_t block_triangles,
                                                           const std::vector<TriangleId>& removed,
                                                           const std::vector<Item>& items) const {
  if (MeshBlockEncodedSize(static_cast<std::int64_t>(removed.size()), 0,
                           static_cast<std::int64_t>(items.size())) > max_message_bytes_) {
    return std::nullopt;
  }
  auto m = Header(key, version);
  m.base_version = base;
  m.block_triangles = block_triangles;
  m.num_removed = static_cast<std::int32_t>(removed.size());
  m.removed_triangle_ids.assign(removed.begin(), removed.end());
  std::unordered_map<VertexId, std::int32_t> local;
  for (const Item& item : items) AddItem(&m, &local, item);
  if (m.getEncodedSize() > max_message_bytes_) return std::nullopt;
  return Encode(m);
}

std::vector<EncodedMessage> MeshBlockSender::Apply(const MeshDelta& delta) {
  frame_id_ = delta.frame_id;
  std::vector<EncodedMessage> out;
  std::set<BlockKey> changed;
  // Removals first: a vertex they release may be upserted again by this delta.
  for (auto id : delta.removed_triangle_ids) {
    auto it = live_cell_.find(id);
    if (it == live_cell_.end()) continue;
    LiveBlock& block = live_.at(it->second);
    auto t = block.triangles.find(id);
    const Triangle vertices = t->second;
    block.triangles.erase(t);
    DropLive(block, id, vertices);
    changed.insert(it->second);
    live_cell_.erase(it);
  }
  std::vector<VertexId> upserted;
  for (size_t i = 0; i < delta.vertex_ids.size(); ++i) {
    Vertex& v = vertices_[delta.vertex_ids[i]];
    v.position = delta.vertex_positions[i].cast<float>();
    if (!delta.vertex_colors_rgb.empty()) v.color = delta.vertex_colors_rgb[i];
    if (!delta.vertex_labels.empty()) v.label = static_cast<std::uint8_t>(delta.vertex_labels[i]);
    upserted.push_back(delta.vertex_ids[i]);
  }
  for (size_t i = 0; i < delta.added_triangle_ids.size(); ++i) {
    const Triangle& t = delta.added_triangles[i];
    if (std::any_of(t.begin(), t.end(), [&](VertexId v) { return vertices_.count(v) == 0; })) continue;
    const BlockKey key = CellOf(t);
    auto [it, created] = live_.try_emplace(key);
    if (created) order_.push_back(key);
    it->second.triangles[delta.added_triangle_ids[i]] = t;
    it->second.added[delta.added_triangle_ids[i]] = t;
    it->second.changed = true;
    for (auto v : t) ++vertices_.at(v).refs;
    live_cell_[delta.added_triangle_ids[i]] = key;
    changed.insert(key);
    ++live_triangles_;
  }
  // Finalised triangles leave their live block for a new finalised block of the same cell, sent once.
  std::map<BlockKey, std::vector<Item>> finalised;
  for (auto id : delta.finalised_triangle_ids) {
    auto it = live_cell_.find(id);
    if (it != live_cell_.end()) finalised[it->second].push_back({id, live_.at(it->second).triangles.at(id)});
  }
  for (auto& [cell, items] : finalised) {
    LiveBlock& block = live_.at(cell);
    BlockKey key = cell;
    key.serial = block.next_serial++;
    FinalBlock& fb = final_[key];
    fb.parts = EncodeWhole(key, 1, true, items);
    fb.triangles = static_cast<std::int32_t>(items.size());
    finalised_triangles_ += fb.triangles;
    order_.push_back(key);
    out.insert(out.end(), fb.parts.begin(), fb.parts.end());
    for (const Item& item : items) {
      block.triangles.erase(item.id);
      DropLive(block, item.id, item.vertices);
      live_cell_.erase(item.id);
    }
    changed.insert(cell);
  }
  for (auto v : upserted) {
    auto it = vertices_.find(v);
    if (it != vertices_.end() && it->second.refs <= 0) vertices_.erase(it);
  }
  for (const BlockKey& key : changed) {
    LiveBlock& block = live_.at(key);
    if (!block.changed) continue;
    const std::int32_t version = block.version + 1;
    std::vector<Item> added;
    for (const auto& [id, t] : block.added) added.push_back({id, t});
    std::optional<EncodedMessage> as_delta;
    const auto whole_estimate =
        kBlockFixedBytes + kWholeBytesPerTriangle * std::int64_t(block.triangles.size());
    if (block.version > 0) {
      as_delta = EncodeDelta(key, block.version, version, static_cast<std::int32_t>(block.triangles.size()),
                             block.removed, added);
      if (as_delta && static_cast<std::int64_t>(as_delta->size()) >= whole_estimate) as_delta.reset();
    }
    block.whole.clear();
    block.version = version;
    if (as_delta) {
      out.push_back(std::move(*as_delta));
    } else {
      std::vector<Item> items;
      for (const auto& [id, t] : block.triangles) items.push_back({id, t});
      block.whole = EncodeWhole(key, version, false, items);
      out.insert(out.end(), block.whole.begin(), block.whole.end());
    }
    block.removed.clear();
    block.added.clear();
    block.changed = false;
  }
  return out;
}

const std::vector<EncodedMessage>& MeshBlockSender::PartsOf(size_t order_index) {
  const BlockKey& key = order_[order_index];
  if (key.serial > 0) return final_.at(key).parts;
  LiveBlock& block = live_.at(key);
  if (block.whole.empty()) {
    std::vector<Item> items;
    for (const auto& [id, t] : block.triangles) items.push_back({id, t});
    block.whole = EncodeWhole(key, std::max(block.version, 1), false, items);
  }
  return block.whole;
}

std::optional<EncodedMessage> MeshBlockSender::NextResend(bool* end_of_round) {
  *end_of_round = false;
  if (order_.empty()) return std::nullopt;
  if (cursor_block_ >= order_.size()) cursor_block_ = cursor_part_ = 0;
  const auto& parts = PartsOf(cursor_block_);
  EncodedMessage msg = parts[std::min(cursor_part_, parts.size() - 1)];
  if (++cursor_part_ >= parts.size()) {
    cursor_part_ = 0;
    if (++cursor_block_ >= order_.size()) {
      cursor_block_ = 0;
      *end_of_round = true;
    }
  }
  return msg;
}

std::vector<EncodedMessage> MeshBlockSender::Index(std::int32_t rounds_left) const {
  const std::int64_t per_part =
      std::max<std::int64_t>(1, (max_message_bytes_ - kEndFixedBytes) / kBytesPerIndexEntry);
  const std::int64_t total = static_cast<std::int64_t>(order_.size());
  const std::int64_t num_parts = std::max<std::int64_t>(1, (total + per_part - 1) / per_part);
  std::vector<EncodedMessage> out;
  for (std::int64_t p = 0; p < num_parts; ++p) {
    semap_lcm::mesh_end_t m{};
    m.utime = NowUtime();
    m.run_id = run_id_;
    m.frame_id = frame_id_;
    m.rounds_left = rounds_left;
    m.part = static_cast<std::int32_t>(p);
    m.num_parts = static_cast<std::int32_t>(num_parts);
    m.total_blocks = static_cast<std::int32_t>(total);
    m.total_triangles = num_triangles();
    for (std::int64_t i = p * per_part; i < std::min(total, (p + 1) * per_part); ++i) {
      const BlockKey& key = order_[i];
      m.blocks.push_back({key.x, key.y, key.z, key.serial});
      if (key.serial > 0) {
        m.versions.push_back(1);
        m.triangles.push_back(final_.at(key).triangles);
      } else {
        const LiveBlock& block = live_.at(key);
        m.versions.push_back(std::max(block.version, 1));
        m.triangles.push_back(static_cast<std::int32_t>(block.triangles.size()));
      }
      ++m.num_blocks;
    }
    out.push_back(Encode(m));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------
// MeshBlockAssembler

void MeshBlockAssembler::StartRun(std::int64_t run_id) {
  run_id_ = run_id;
  have_run_ = true;
  vertices_.clear();
  blocks_.clear();
  index_ = {};
  complete_ = {};
  counters_.run_ended = counters_.closing_seen = false;
  ++counters_.runs;
}

void MeshBlockAssembler::TakeVertices(const semap_lcm::mesh_block_t& m) {
  for (std::int32_t i = 0; i < m.num_vertices; ++i) {
    Vertex& v = vertices_[static_cast<VertexId>(m.vertex_ids[i])];
    v.position = {m.positions[i][0], m.positions[i][1], m.positions[i][2]};
    v.color = {static_cast<std::uint8_t>(m.colors[i][0]), static_cast<std::uint8_t>(m.colors[i][1]),
               static_cast<std::uint8_t>(m.colors[i][2])};
    v.label = static_cast<std::uint8_t>(m.labels[i]);
  }
}

void MeshBlockAssembler::AddTriangles(const semap_lcm::mesh_block_t& m, std::map<TriangleId, Triangle>* to) {
  for (std::int32_t i = 0; i < m.num_triangles; ++i) {
    Triangle t;
    for (int k = 0; k < 3; ++k) t[k] = static_cast<VertexId>(m.vertex_ids[m.triangles[i][k]]);
    (*to)[static_cast<TriangleId>(m.triangle_ids[i])] = t;
  }
}

void MeshBlockAssembler::Add(const semap_lcm::mesh_block_t& m) {
  if (!have_run_ || m.run_id != run_id_) StartRun(m.run_id);
  Block& b = blocks_[{m.block[0], m.block[1], m.block[2], m.serial}];
  b.latest_seen = std::max(b.latest_seen, m.version);
  if (m.version <= b.version) {
    ++counters_.duplicates;
    return;
  }
  if (m.base_version > 0) {  // a delta
    if (b.version == 0 || b.version != m.base_version) {
      ++counters_.deltas_without_base;
      return;
    }
    for (auto id : m.removed_triangle_ids) b.triangles.erase(static_cast<TriangleId>(id));
    TakeVertices(m);
    AddTriangles(m, &b.triangles);
    b.version = m.version;
    if (b.pending_version <= b.version) b.pending_version = 0;
    ++counters_.messages;
    if (static_cast<std::int64_t>(b.triangles.size()) !=
        m.block_triangles) {  // should not happen: wait for a re-send
      b.version = 0;
      b.triangles.clear();
    }
    return;
  }
  if (m.version < b.pending_version) {
    ++counters_.duplicates;  // older than the version being assembled
    return;
  }
  if (m.version > b.pending_version || b.pending_got.size() != static_cast<size_t>(m.num_parts)) {
    b.pending_version = m.version;
    b.pending_got.assign(m.num_parts, false);
    b.pending.clear();
  }
  if (b.pending_got[m.part]) {
    ++counters_.duplicates;
    return;
  }
  b.pending_got[m.part] = true;
  TakeVertices(m);
  AddTriangles(m, &b.pending);
  ++counters_.messages;
  if (std::all_of(b.pending_got.begin(), b.pending_got.end(), [](bool g) { return g; })) {
    b.version = b.pending_version;
    b.triangles = std::move(b.pending);
    b.pending = {};
    b.pending_got.clear();
    b.pending_version = 0;
  }
}

void MeshBlockAssembler::Add(const semap_lcm::mesh_end_t& m) {
  if (!have_run_ || m.run_id != run_id_) StartRun(m.run_id);
  ++counters_.index_messages;
  counters_.closing_seen = counters_.closing_seen || m.rounds_left >= 0;
  if (m.rounds_left == 0) counters_.run_ended = true;
  if (index_.num_parts != m.num_parts || index_.total_blocks != m.total_blocks || index_.got.empty()) {
    index_ = {};
    index_.num_parts = m.num_parts;
    index_.total_blocks = m.total_blocks;
    index_.got.assign(m.num_parts, false);
  }
  if (index_.got[m.part]) {
    // A part of a later index (same shape): start over from it.
    index_.versions.clear();
    std::fill(index_.got.begin(), index_.got.end(), false);
  }
  index_.got[m.part] = true;
  for (std::int32_t i = 0; i < m.num_blocks; ++i) {
    const auto& k = m.blocks[i];
    index_.versions[{k[0], k[1], k[2], k[3]}] = m.versions[i];
  }
  if (std::all_of(index_.got.begin(), index_.got.end(), [](bool g) { return g; })) {
    complete_ = index_;
    complete_.complete = true;
    index_ = {};
  }
}

Mesh MeshBlockAssembler::ToMesh() const {
  std::map<TriangleId, Triangle> triangles;
  for (const auto& [key, b] : blocks_) {
    if (b.version > 0) triangles.insert(b.triangles.begin(), b.triangles.end());
  }
  std::map<VertexId, std::uint32_t> index;
  for (const auto& [id, t] : triangles) {
    for (auto v : t) index.emplace(v, 0);
  }
  Mesh mesh;
  for (auto& [vid, idx] : index) {
    const Vertex& v = vertices_.at(vid);  // every held triangle came with its vertices
    idx = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(v.position.cast<double>());
    mesh.colors_rgb.push_back(v.color);
    mesh.labels.push_back(v.label);
  }
  for (const auto& [id, t] : triangles) mesh.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
  return mesh;
}

std::int64_t MeshBlockAssembler::num_triangles() const {
  std::int64_t n = 0;
  for (const auto& [key, b] : blocks_) n += b.version > 0 ? static_cast<std::int64_t>(b.triangles.size()) : 0;
  return n;
}

std::vector<std::string> MeshBlockAssembler::Missing() const {
  std::vector<std::string> out;
  for (const auto& [key, b] : blocks_) {
    std::int32_t target = b.latest_seen;
    if (auto it = complete_.versions.find(key); it != complete_.versions.end())
      target = std::max(target, it->second);
    if (b.version >= target) continue;
    std::string line =
        key.ToString() + ": " +
        (b.version > 0 ? "holds version " + std::to_string(b.version) : std::string("holds nothing")) +
        ", lacks version " + std::to_string(target);
    if (b.pending_version == target) {
      const auto got = std::count(b.pending_got.begin(), b.pending_got.end(), true);
      line += " (parts " + std::to_string(got) + "/" + std::to_string(b.pending_got.size()) + " received)";
    }
    out.push_back(line);
  }
  for (const auto& [key, version] : complete_.versions) {
    if (blocks_.count(key) == 0)
      out.push_back(key.ToString() + ": never received (version " + std::to_string(version) + ")");
  }
  return out;
}

bool MeshBlockAssembler::Complete() const {
  if (!complete_.complete) return false;
  for (const auto& [key, version] : complete_.versions) {
    auto it = blocks_.find(key);
    if (it == blocks_.end() || it->second.version < version) return false;
  }
  return true;
}

bool MeshBlockAssembler::Holds(const MeshBlockAssembler& other) const {
  for (const auto& [key, b] : other.blocks_) {
    if (b.version == 0) continue;
    auto it = blocks_.find(key);
    if (it == blocks_.end() || it->second.version < b.version) return false;
  }
  return true;
}

}  // namespace semap::io
