// The mesh cut into bounded spatial blocks for LCM (semap_lcm::mesh_block_t), so that a late or lossy
// subscriber can rebuild it: MeshBlockSender (publisher side) turns engine MeshDeltas into block messages and
// re-sends block states round-robin; MeshBlockAssembler (subscriber side) rebuilds the mesh from any subset
// of those messages, in any order, and names the blocks it still lacks.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "engine/core/mesh_delta.h"
#include "semap_lcm/mesh_block_t.hpp"
#include "semap_lcm/mesh_end_t.hpp"

namespace semap::io {

// A block: the cell (floor(centroid / block_size)) and serial (0: the cell's live triangles; k >= 1: its
// k-th finalised block).
struct BlockKey {
  std::int32_t x = 0, y = 0, z = 0, serial = 0;
  auto operator<=>(const BlockKey&) const = default;
  std::string ToString() const;  // "(x,y,z)#serial"
};

// One encoded LCM message (the bytes lcm::LCM::publish sends).
using EncodedMessage = std::vector<std::uint8_t>;

// Publisher side. Keeps the live triangles per block (bounded by the live mesh) and the encoded messages of
// finalised blocks (about 40 bytes per finalised triangle, for the re-sends). Not thread-safe.
class MeshBlockSender {
 public:
  // `max_message_bytes`: bound on every encoded message; `block_size_m`: cell edge; `run_id` tags every
  // message of the run.
  MeshBlockSender(double block_size_m, int max_message_bytes, std::int64_t run_id);

  // Applies one delta and returns the messages that carry its changes: for each changed live block a delta
  // against its previous version when that fits one message and is smaller than the whole state, else the
  // whole state (in parts); for each cell with newly finalised triangles a finalised block (in parts).
  std::vector<EncodedMessage> Apply(const MeshDelta& delta);

  // The next message of the round-robin re-send of every block's whole current state (one part at a time);
  // `end_of_round` is set when this message completes a round over all blocks. Empty when there is no block.
  std::optional<EncodedMessage> NextResend(bool* end_of_round);
  // Restarts the round-robin at the first block (closing rounds start from there).
  void RestartResend() { cursor_block_ = cursor_part_ = 0; }
  // The index of every block and its version (mesh_end_t messages, in parts).
  std::vector<EncodedMessage> Index(std::int32_t rounds_left) const;

  size_t num_blocks() const { return order_.size(); }
  std::int64_t num_triangles() const { return live_triangles_ + finalised_triangles_; }

 private:
  struct Vertex {
    Eigen::Vector3f position;
    std::array<std::uint8_t, 3> color{200, 200, 200};
    std::uint8_t label = 0;
    std::int32_t refs = 0;  // live triangles using it
  };
  using Triangle = std::array<VertexId, 3>;
  struct LiveBlock {
    std::int32_t version = 0;  // last version sent (0: never)
    std::int32_t next_serial = 1;
    std::map<TriangleId, Triangle> triangles;
    std::vector<TriangleId> removed;       // since the last version, of triangles sent in it
    std::map<TriangleId, Triangle> added;  // since the last version
    std::vector<EncodedMessage> whole;     // the whole state's parts at `version` (built lazily)
    bool changed = false;
  };
  struct FinalBlock {
    std::vector<EncodedMessage> parts;
    std::int32_t triangles = 0;
  };
  struct Item {  // a triangle with its vertices, ready to encode
    TriangleId id;
    Triangle vertices;
  };

  BlockKey CellOf(const Triangle& t) const;
  void DropLive(LiveBlock& block, TriangleId id, const Triangle& t);
  // The messages of a whole state (base_version 0) or a delta (one part; nullopt if it does not fit).
  std::vector<EncodedMessage> EncodeWhole(const BlockKey& key, std::int32_t version, bool finalised,
                                          const std::vector<Item>& items) const;
  std::optional<EncodedMessage> EncodeDelta(const BlockKey& key, std::int32_t base, std::int32_t version,
                                            std::int32_t block_triangles,
                                            const std::vector<TriangleId>& removed,
                                            const std::vector<Item>& items) const;
  semap_lcm::mesh_block_t Header(const BlockKey& key, std::int32_t version) const;
  void AddItem(semap_lcm::mesh_block_t* msg, std::unordered_map<VertexId, std::int32_t>* local,
               const Item& item) const;
  const std::vector<EncodedMessage>& PartsOf(size_t order_index);

  double block_size_m_;
  int max_message_bytes_;
  std::int64_t run_id_;
  std::int64_t frame_id_ = -1;
  std::unordered_map<VertexId, Vertex> vertices_;
  std::unordered_map<TriangleId, BlockKey> live_cell_;  // live triangle → its block
  std::map<BlockKey, LiveBlock> live_;
  std::map<BlockKey, FinalBlock> final_;
  std::vector<BlockKey> order_;  // every block, in order of creation (the round-robin)
  size_t cursor_block_ = 0, cursor_part_ = 0;
  std::int64_t live_triangles_ = 0, finalised_triangles_ = 0;
};

// Bytes of an encoded mesh_block_t / mesh_end_t with these counts (LCM fingerprint included).
std::int64_t MeshBlockEncodedSize(std::int64_t removed, std::int64_t vertices, std::int64_t triangles);
std::int64_t MeshEndEncodedSize(std::int64_t blocks);

// Decodes a message after checking its counts against its length (a count that does not match the length
// would make the generated decoder allocate before it notices), its fingerprint and its content (indices in
// range, finite positions, consistent parts and versions). Returns nullopt and sets `error` otherwise.
std::optional<semap_lcm::mesh_block_t> DecodeMeshBlock(const void* data, size_t size, std::string* error);
std::optional<semap_lcm::mesh_end_t> DecodeMeshEnd(const void* data, size_t size, std::string* error);

// Subscriber side: rebuilds the mesh from block messages received in any order, any of them lost or
// repeated. Keeps the blocks of one run (a message of another run id starts over). Not thread-safe.
class MeshBlockAssembler {
 public:
  struct Counters {
    std::int64_t messages = 0;    // block messages accepted
    std::int64_t duplicates = 0;  // parts or versions already held, or older than held
    std::int64_t deltas_without_base =
        0;                  // deltas skipped: their base version is not held (a re-send fixes it)
    std::int64_t runs = 0;  // run ids seen (a new one resets the mesh)
    std::int64_t index_messages = 0;
    bool closing_seen = false;  // an index of the run's closing rounds (rounds_left >= 0) arrived
    bool run_ended = false;     // the last message of the run (mesh_end_t with rounds_left 0) arrived
  };
  void Add(const semap_lcm::mesh_block_t& msg);
  void Add(const semap_lcm::mesh_end_t& msg);

  // The mesh of every block held (its latest complete version); triangles are deduplicated by id,
  // vertices ordered by id.
  Mesh ToMesh() const;
  std::int64_t num_triangles() const;
  // Blocks that are incomplete, behind a version seen or listed in the latest index, or listed there and
  // never received: one line each, e.g. "(1,0,-2)#0: holds version 3, lacks version 5 (parts 1/2 received)".
  std::vector<std::string> Missing() const;
  // Every block listed in the latest complete index is held at its listed version.
  bool Complete() const;
  // Every block that `other` holds is held here at the same version or a later one.
  bool Holds(const MeshBlockAssembler& other) const;
  const Counters& counters() const { return counters_; }

 private:
  struct Vertex {
    Eigen::Vector3f position;
    std::array<std::uint8_t, 3> color{0, 0, 0};
    std::uint8_t label = 0;
  };
  using Triangle = std::array<VertexId, 3>;
  struct Block {
    std::int32_t version = 0;  // complete version held (0: none)
    std::map<TriangleId, Triangle> triangles;
    std::int32_t pending_version = 0;  // whole state being assembled from parts
    std::vector<bool> pending_got;
    std::map<TriangleId, Triangle> pending;
    std::int32_t latest_seen = 0;  // highest version in any message
  };
  struct Index {
    std::map<BlockKey, std::int32_t> versions;
    std::int32_t total_blocks = -1;
    std::int32_t num_parts = 0;
    std::vector<bool> got;
    bool complete = false;
  };
  void StartRun(std::int64_t run_id);
  void TakeVertices(const semap_lcm::mesh_block_t& msg);
  static void AddTriangles(const semap_lcm::mesh_block_t& msg, std::map<TriangleId, Triangle>* to);

  std::int64_t run_id_ = 0;
  bool have_run_ = false;
  std::unordered_map<VertexId, Vertex> vertices_;
  std::map<BlockKey, Block> blocks_;
  Index index_;     // being assembled
  Index complete_;  // the latest complete index
  Counters counters_;
};

}  // namespace semap::io
