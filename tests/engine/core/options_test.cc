#include "engine/core/options.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

namespace semap {
namespace {

// An options struct declared the way every stage's is.
enum class Shape { kRound, kSquare };

struct ToyOptions {
  int count = 3;
  double ratio = 0.5;
  int window_px = 7;
  float offset_px = -1.0f;
  std::string name = "toy";
  std::vector<int> ids;
  Shape shape = Shape::kRound;
  double low = 1.0;
  double high = 2.0;

  template <typename Visitor>
  void Describe(Visitor& v) {
    v.Field("count", &count, "how many", AtLeast(1));
    v.Field("ratio", &ratio, "a share", AtLeast(0).Below(1));
    v.Field("window_px", &window_px, "a window", In(3, 11).Odd());
    v.Field("offset_px", &offset_px, "an offset", AtLeast(0).Or(-1, "off"));
    v.Field("name", &name, "a name", NotEmpty());
    v.Field("ids", &ids, "ids", AtLeast(0).Below(8));
    v.Enum("shape", &shape, {{"round", Shape::kRound}, {"square", Shape::kSquare}}, "a shape");
    v.Field("low", &low, "the low end");
    v.Field("high", &high, "the high end, above low");
  }

  void Check() const {
    CheckDeclaredRanges(*this);
    if (high <= low) throw OptionError(*this, high, "must be greater than " + KeyOf(*this, low));
  }
};

// The error Check() throws, as the config loader would print it after the section ("key: message").
std::string ErrorOf(const ToyOptions& o) {
  try {
    o.Check();
  } catch (const InvalidOption& e) {
    return e.what();
  }
  return "";
}

TEST(Options, RangesSayWhatTheyAdmit) {
  EXPECT_EQ(AtLeast(1).Text(), ">= 1");
  EXPECT_EQ(Above(0).Text(), "> 0");
  EXPECT_EQ(AtLeast(0).Below(1).Text(), "in [0, 1)");
  EXPECT_EQ(Above(0).AtMost(2).Text(), "in (0, 2]");
  EXPECT_EQ(In(0.05, 1e4).Text(), "in [0.05, 10000]");
  EXPECT_EQ(In(1, 1000000).Text(), "in [1, 1000000]");
  EXPECT_EQ(In(0, Bound(1.0 / 3.0, "1/3")).Text(), "in [0, 1/3]");
  EXPECT_EQ(In(1, 11).Odd().Text(), "odd and in [1, 11]");
  EXPECT_EQ(AtLeast(16).MultipleOf(16).Text(), "a multiple of 16 and >= 16");
  EXPECT_EQ(AtLeast(0).Or(-1, "off").Requirement(), "must be >= 0, or -1 (off)");

  const Range share = AtLeast(0).Below(1);
  EXPECT_TRUE(share.Admits(0.0));
  EXPECT_TRUE(share.Admits(0.999));
  EXPECT_FALSE(share.Admits(1.0));
  EXPECT_FALSE(share.Admits(-1e-9));
  EXPECT_FALSE(share.Admits(std::numeric_limits<double>::quiet_NaN()));
  const Range odd = In(1, 11).Odd();
  EXPECT_TRUE(odd.Admits(1));
  EXPECT_TRUE(odd.Admits(11));
  EXPECT_FALSE(odd.Admits(4));
  EXPECT_FALSE(odd.Admits(13));
  const Range sixteens = AtLeast(16).MultipleOf(16);
  EXPECT_TRUE(sixteens.Admits(128));
  EXPECT_FALSE(sixteens.Admits(100));
  EXPECT_FALSE(sixteens.Admits(0));
  const Range or_off = AtLeast(0).Or(-1, "off");
  EXPECT_TRUE(or_off.Admits(-1));
  EXPECT_TRUE(or_off.Admits(0.5));
  EXPECT_FALSE(or_off.Admits(-0.5));
}

TEST(Options, CheckNamesTheKeyAndTheValueOfTheFirstFieldOutOfRange) {
  EXPECT_EQ(ErrorOf(ToyOptions{}), "");
  ToyOptions o;
  o.count = 0;
  EXPECT_EQ(ErrorOf(o), "count: must be >= 1 (got 0)");
  o = {};
  o.ratio = 1.0;
  EXPECT_EQ(ErrorOf(o), "ratio: must be in [0, 1) (got 1)");
  o = {};
  o.window_px = 8;
  EXPECT_EQ(ErrorOf(o), "window_px: must be odd and in [3, 11] (got 8)");
  o = {};
  o.offset_px = -0.5f;
  EXPECT_EQ(ErrorOf(o), "offset_px: must be >= 0, or -1 (off) (got -0.5)");
  o = {};
  o.name.clear();
  EXPECT_EQ(ErrorOf(o), "name: must not be empty (got '')");
  o = {};
  o.ids = {0, 9};
  EXPECT_EQ(ErrorOf(o), "ids: each must be in [0, 8) (got 9)");
  o = {};
  o.count = 0;
  o.ratio = 2.0;
  EXPECT_EQ(ErrorOf(o), "count: must be >= 1 (got 0)") << "the first in Describe()'s order";
}

TEST(Options, NonFiniteNumbersAreRefusedWithOrWithoutARange) {
  ToyOptions o;
  o.ratio = std::numeric_limits<double>::infinity();
  EXPECT_EQ(ErrorOf(o), "ratio: must be a finite number (got inf)");
  o = {};
  o.low = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ErrorOf(o), "low: must be a finite number (got nan)");
  try {
    o.Check();
    FAIL() << "no throw";
  } catch (const InvalidOption& e) {
    EXPECT_EQ(e.field(), "low");
  }
}

TEST(Options, CrossFieldChecksNameTheirFieldsThroughTheDeclaration) {
  ToyOptions o;
  EXPECT_EQ(KeyOf(o, o.window_px), "window_px");
  EXPECT_EQ(KeyOf(o, o.shape), "shape");
  EXPECT_EQ(KeyOf(o, o.ids), "ids");
  o.high = 1.0;
  EXPECT_EQ(ErrorOf(o), "high: must be greater than low (got 1)");
  const ToyOptions& constant = o;  // Check() is const: the declaration is read from a const struct
  EXPECT_EQ(KeyOf(constant, constant.high), "high");
  EXPECT_EQ(std::string(OptionError(o, o.ids, "too many", 42).what()), "ids: too many (got 42)");
}

}  // namespace
}  // namespace semap
