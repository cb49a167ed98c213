#include "io/lcm/mesh_blocks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <set>

#include "tests/io/lcm/lcm_test_mesh.h"

namespace semap::io {
namespace {

semap_lcm::mesh_block_t DecodeOrFail(const EncodedMessage& m) {
  std::string error;
  auto msg = DecodeMeshBlock(m.data(), m.size(), &error);
  EXPECT_TRUE(msg.has_value()) << error;
  return msg.value_or(semap_lcm::mesh_block_t{});
}

// Feeds block and index messages (told apart by their fingerprint) to an assembler.
void Feed(const std::vector<EncodedMessage>& messages, MeshBlockAssembler* a) {
  for (const auto& m : messages) {
    std::string error;
    if (auto b = DecodeMeshBlock(m.data(), m.size(), &error)) {
      a->Add(*b);
    } else if (auto e = DecodeMeshEnd(m.data(), m.size(), &error)) {
      a->Add(*e);
    } else {
      ADD_FAILURE() << error;
    }
  }
}

// One round of re-sends (every block's whole state, every part) and the index.
std::vector<EncodedMessage> OneRound(MeshBlockSender* sender, std::int32_t rounds_left) {
  std::vector<EncodedMessage> out;
  sender->RestartResend();
  bool end = false;
  while (!end) out.push_back(*sender->NextResend(&end));
  for (auto& m : sender->Index(rounds_left)) out.push_back(std::move(m));
  return out;
}

TEST(MeshBlocks, EncodedSizesMatchTheGeneratedCode) {
  semap_lcm::mesh_block_t b{};
  b.num_removed = 2;
  b.removed_triangle_ids = {1, 2};
  b.num_vertices = 3;
  b.vertex_ids = {1, 2, 3};
  b.positions.assign(3, std::vector<float>(3, 0.f));
  b.colors.assign(3, std::vector<std::uint8_t>(3, 0));
  b.labels.assign(3, 0);
  b.num_triangles = 1;
  b.triangle_ids = {9};
  b.triangles.assign(1, std::vector<std::int32_t>{0, 1, 2});
  EXPECT_EQ(MeshBlockEncodedSize(2, 3, 1), b.getEncodedSize());
  semap_lcm::mesh_end_t e{};
  e.num_blocks = 2;
  e.blocks.assign(2, std::vector<std::int32_t>(4, 0));
  e.versions = {1, 2};
  e.triangles = {3, 4};
  EXPECT_EQ(MeshEndEncodedSize(2), e.getEncodedSize());
}

// Every message the sender makes, applied in order, rebuilds the mesh; messages stay within the bound; big
// blocks go in parts, small changes as deltas, finalised triangles in finalised blocks.
TEST(MeshBlocks, MessagesInOrderRebuildTheMeshWithinTheBound) {
  constexpr int kMax = 2048;
  test::EvolvingMesh source(11);
  MeshBlockSender sender(40.0, kMax, 42);  // about two cells: blocks of a few parts
  MeshBlockAssembler assembler;
  std::int64_t parts = 0, deltas = 0, finalised = 0;
  for (int frame = 0; frame < 40; ++frame) {
    const auto messages = sender.Apply(source.Step(frame));
    for (const auto& m : messages) {
      ASSERT_LE(static_cast<int>(m.size()), kMax);
      const auto b = DecodeOrFail(m);
      parts += b.num_parts > 1 ? 1 : 0;
      deltas += b.base_version > 0 ? 1 : 0;
      finalised += b.finalised ? 1 : 0;
    }
    Feed(messages, &assembler);
    ASSERT_EQ(test::Soup(assembler.ToMesh()), test::Soup(source.truth().ToMesh())) << "frame " << frame;
  }
  EXPECT_GT(parts, 0);
  EXPECT_GT(deltas, 0);
  EXPECT_GT(finalised, 0);
  EXPECT_EQ(sender.num_triangles(), static_cast<std::int64_t>(source.truth().num_triangles()));
  EXPECT_TRUE(assembler.Missing().empty());
  Feed(sender.Index(0), &assembler);
  EXPECT_TRUE(assembler.Complete());
  EXPECT_TRUE(assembler.counters().run_ended);
}

// A subscriber that joins at the end, with the messages in any order, repeated: one round of re-sends is
// enough.
TEST(MeshBlocks, OneRoundOfResendsInAnyOrderRebuildsTheMesh) {
  test::EvolvingMesh source(5);
  MeshBlockSender sender(8.0, 2048, 7);
  for (int frame = 0; frame < 30; ++frame) sender.Apply(source.Step(frame));
  auto round = OneRound(&sender, 0);
  std::mt19937 rng(1);
  std::shuffle(round.begin(), round.end(), rng);
  const auto again = round;
  round.insert(round.end(), again.begin(), again.begin() + static_cast<long>(again.size() / 2));
  MeshBlockAssembler late;
  Feed(round, &late);
  EXPECT_EQ(test::Soup(late.ToMesh()), test::Soup(source.truth().ToMesh()));
  EXPECT_TRUE(late.Complete());
  EXPECT_TRUE(late.Missing().empty());
  EXPECT_GT(late.counters().duplicates, 0);
}

// A subscriber that joins late: deltas whose base it never got wait for a re-send; a part lost from the
// re-send round is named (block, versions, parts received); the next round completes the mesh.
TEST(MeshBlocks, LostPartsAndBasesAreNamedAndRecovered) {
  test::EvolvingMesh source(11);
  MeshBlockSender sender(40.0, 2048, 9);
  MeshBlockAssembler a;
  for (int frame = 0; frame < 20; ++frame) {
    const auto messages = sender.Apply(source.Step(frame));
    if (frame >= 10 && frame < 15) Feed(messages, &a);  // joins at frame 10, loses frames 15..19
  }
  EXPECT_GT(a.counters().deltas_without_base, 0);
  auto round = OneRound(&sender, 0);
  auto lost = std::find_if(round.begin(), round.end(), [](const EncodedMessage& m) {
    std::string error;
    const auto b = DecodeMeshBlock(m.data(), m.size(), &error);
    return b && b->serial == 0 && b->num_parts > 1 && b->part == 1;
  });
  ASSERT_NE(lost, round.end());
  const auto lost_msg = DecodeOrFail(*lost);
  round.erase(lost);
  Feed(round, &a);
  EXPECT_FALSE(a.Complete());
  const auto missing = a.Missing();
  const std::string key = BlockKey{lost_msg.block[0], lost_msg.block[1], lost_msg.block[2], 0}.ToString();
  const std::string parts = "(parts " + std::to_string(lost_msg.num_parts - 1) + "/" +
                            std::to_string(lost_msg.num_parts) + " received)";
  ASSERT_EQ(missing.size(), 1u) << ::testing::PrintToString(missing);
  EXPECT_EQ(missing[0].find(key), 0u) << missing[0];
  EXPECT_NE(missing[0].find("lacks version " + std::to_string(lost_msg.version) + " " + parts),
            std::string::npos)
      << missing[0];
  Feed(OneRound(&sender, 0), &a);
  EXPECT_TRUE(a.Complete());
  EXPECT_TRUE(a.Missing().empty());
  EXPECT_EQ(test::Soup(a.ToMesh()), test::Soup(source.truth().ToMesh()));
}

TEST(MeshBlocks, MessagesOfANewRunReplaceTheOldRun) {
  test::EvolvingMesh one(1), two(2);
  MeshBlockSender first(8.0, 4096, 1), second(8.0, 4096, 2);
  MeshBlockAssembler a;
  Feed(first.Apply(one.Step(0)), &a);
  Feed(second.Apply(two.Step(0)), &a);
  EXPECT_EQ(a.counters().runs, 2);
  EXPECT_EQ(test::Soup(a.ToMesh()), test::Soup(two.truth().ToMesh()));
}

// Damaged messages are refused with a reason, before the generated decoder could allocate for a count.
class DamagedBlock : public ::testing::Test {
 protected:
  void SetUp() override {
    test::EvolvingMesh source(4);
    MeshBlockSender sender(100.0, 60000, 3);
    good_ = sender.Apply(source.Step(0)).front();
    msg_ = DecodeOrFail(good_);
    ASSERT_GE(msg_.num_vertices, 3);
  }
  std::string Refusal(const EncodedMessage& bytes) {
    std::string error;
    EXPECT_FALSE(DecodeMeshBlock(bytes.data(), bytes.size(), &error).has_value());
    return error;
  }
  std::string Refusal(const semap_lcm::mesh_block_t& m) {
    EncodedMessage bytes(static_cast<size_t>(m.getEncodedSize()));
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    return Refusal(bytes);
  }
  EncodedMessage good_;
  semap_lcm::mesh_block_t msg_;
};

TEST_F(DamagedBlock, HugeOrNegativeCountsAreRefusedByLength) {
  auto bytes = good_;
  for (int i : {12, 13, 14, 15}) bytes[i] = i == 12 ? 0x7f : 0xff;  // num_vertices = 2^31 - 1
  EXPECT_NE(Refusal(bytes).find("2147483647"), std::string::npos);
  bytes = good_;
  bytes[16] = 0xff;  // num_triangles negative
  EXPECT_NE(Refusal(bytes).find("negative count"), std::string::npos);
  EXPECT_NE(Refusal(EncodedMessage(good_.begin(), good_.begin() + 10)).find("too short"), std::string::npos);
  bytes = good_;
  bytes.push_back(0);
  EXPECT_NE(Refusal(bytes).find("the message has"), std::string::npos);
}

TEST_F(DamagedBlock, WrongFingerprintIsRefused) {
  auto bytes = good_;
  bytes[0] ^= 0x55;
  EXPECT_NE(Refusal(bytes).find("fingerprint"), std::string::npos);
}

TEST_F(DamagedBlock, NonFiniteVertexIsRefused) {
  auto m = msg_;
  m.positions[1][2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(Refusal(m).find("vertex " + std::to_string(m.vertex_ids[1]) + " has a non-finite"),
            std::string::npos);
  m = msg_;
  m.positions[0][0] = std::numeric_limits<float>::infinity();
  EXPECT_NE(Refusal(m).find("non-finite"), std::string::npos);
}

TEST_F(DamagedBlock, UnknownVertexIsRefused) {
  auto m = msg_;
  m.triangles[0][1] = m.num_vertices;  // one past the message's vertices
  EXPECT_NE(Refusal(m).find("names vertex " + std::to_string(m.num_vertices)), std::string::npos);
  m.triangles[0][1] = -1;
  EXPECT_NE(Refusal(m).find("names vertex -1"), std::string::npos);
}

TEST_F(DamagedBlock, InconsistentHeaderIsRefused) {
  auto m = msg_;
  m.version = 0;
  EXPECT_NE(Refusal(m).find("version 0"), std::string::npos);
  m = msg_;
  m.part = 5;
  m.num_parts = 2;
  EXPECT_NE(Refusal(m).find("part 5 of 2"), std::string::npos);
  m = msg_;
  m.num_parts = std::numeric_limits<std::int32_t>::max();
  EXPECT_FALSE(Refusal(m).empty());
  m = msg_;
  m.base_version = m.version;
  EXPECT_NE(Refusal(m).find("base_version"), std::string::npos);
  m = msg_;
  m.block_triangles = 0;
  EXPECT_NE(Refusal(m).find("block_triangles"), std::string::npos);
}

TEST(MeshBlocks, DamagedIndexIsRefused) {
  MeshBlockSender sender(8.0, 4096, 1);
  auto bytes = sender.Index(0).front();
  std::string error;
  ASSERT_TRUE(DecodeMeshEnd(bytes.data(), bytes.size(), &error).has_value()) << error;
  for (int i : {8, 9, 10, 11}) bytes[i] = i == 8 ? 0x7f : 0xff;  // num_blocks = 2^31 - 1
  EXPECT_FALSE(DecodeMeshEnd(bytes.data(), bytes.size(), &error).has_value());
  EXPECT_NE(error.find("2147483647"), std::string::npos);
}

}  // namespace
}  // namespace semap::io
