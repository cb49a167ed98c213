#include "engine/core/options.h"

#include <charconv>

namespace semap {

namespace {

// The shortest decimal form that reads back as `value`; whole numbers below 10^15 without an exponent.
std::string Written(const Bound& bound) {
  if (!bound.text.empty()) return bound.text;
  constexpr double kLargestPlain = 1e15;
  const double v = bound.value;
  const bool whole = std::abs(v) < kLargestPlain && v == std::trunc(v);
  char buf[64];
  const auto [end, ec] = whole ? std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed)
                               : std::to_chars(buf, buf + sizeof(buf), v);
  SEMAP_ASSERT(ec == std::errc());
  return std::string(buf, end);
}

}  // namespace

Range AtLeast(Bound lo) {
  Range r;
  r.lo_ = std::move(lo);
  return r;
}

Range Above(Bound lo) {
  Range r = AtLeast(std::move(lo));
  r.lo_open_ = true;
  return r;
}

Range Range::AtMost(Bound hi) const {
  Range r = *this;
  r.hi_ = std::move(hi);
  r.hi_open_ = false;
  return r;
}

Range Range::Below(Bound hi) const {
  Range r = AtMost(std::move(hi));
  r.hi_open_ = true;
  return r;
}

Range Range::Odd() const {
  Range r = *this;
  r.odd_ = true;
  return r;
}

Range Range::MultipleOf(int divisor) const {
  SEMAP_ASSERT(divisor > 1, "MultipleOf needs a divisor > 1");
  Range r = *this;
  r.divisor_ = divisor;
  return r;
}

Range Range::Or(double value, std::string meaning) const {
  Range r = *this;
  r.special_ = value;
  r.special_meaning_ = std::move(meaning);
  return r;
}

bool Range::Admits(double value) const {
  if (special_ && value == *special_) return true;
  if (lo_ && (lo_open_ ? !(value > lo_->value) : !(value >= lo_->value))) return false;
  if (hi_ && (hi_open_ ? !(value < hi_->value) : !(value <= hi_->value))) return false;
  if (odd_ && std::fmod(std::abs(value), 2.0) != 1.0) return false;
  if (divisor_ > 0 && std::fmod(value, divisor_) != 0.0) return false;
  return true;
}

std::string Range::Text() const {
  std::string interval;
  if (lo_ && hi_) {
    interval = std::string("in ") + (lo_open_ ? "(" : "[") + Written(*lo_) + ", " + Written(*hi_) +
               (hi_open_ ? ")" : "]");
  } else if (lo_) {
    interval = (lo_open_ ? "> " : ">= ") + Written(*lo_);
  } else if (hi_) {
    interval = (hi_open_ ? "< " : "<= ") + Written(*hi_);
  }
  std::string text;
  if (odd_) text = "odd";
  if (divisor_ > 0) text += (text.empty() ? "" : " and ") + ("a multiple of " + std::to_string(divisor_));
  if (!interval.empty()) text += (text.empty() ? "" : " and ") + interval;
  if (special_) text += ", or " + Written(*special_) + " (" + special_meaning_ + ")";
  return text;
}

}  // namespace semap
