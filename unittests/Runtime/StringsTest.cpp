//===- StringsTest.cpp - The run-time string functions --------------------===//
//
// osl_rt_string_call on small batches: OSL's semantics per function, lanes
// outside the mask, and the intern table's one-handle-per-string rule under
// concurrent use.
//
//===----------------------------------------------------------------------===//
#include "OslAbi/EntryPoints.h"
#include "OslRuntime/StringCall.h"
#include "OslStrings/StringFunctions.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace {

int32_t handle(const char *s) { return osl_rt_string_intern(s); }

int32_t floatBits(float f) {
  int32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  return bits;
}

/// Calls `name` on one lane with one value per operand; returns the
/// result's bits.
int32_t callOne(const char *name, const char *kinds, std::vector<int32_t> operands) {
  operands.push_back(-1); // the result row
  osl_rt_string_call("test", osl::stringFunctionCode(name), kinds, operands.data(), 1, 1);
  return operands.back();
}

/// The text of a string handle, read back through strlen and getchar.
std::string textOf(int32_t h) {
  int32_t n = callOne("strlen", "s", {h});
  std::string s;
  for (int32_t i = 0; i < n; ++i)
    s += char(callOne("getchar", "si", {h, i}));
  return s;
}

TEST(Strings, EqualStringsHaveEqualHandles) {
  EXPECT_EQ(handle(""), 0);
  EXPECT_EQ(handle("tile"), handle("tile"));
  EXPECT_NE(handle("tile"), handle("tiles"));
  EXPECT_EQ(callOne("concat", "ss", {handle("ti"), handle("le")}), handle("tile"));
}

TEST(Strings, FormatIsPrintfValueByValue) {
  int32_t s = callOne("format", "ssii", {handle("%s_%02d_%d"), handle("tile"), 3, 2});
  EXPECT_EQ(textOf(s), "tile_03_2");
  EXPECT_EQ(textOf(callOne("format", "sf", {handle("%g"), floatBits(-2.25f)})), "-2.25");
  EXPECT_EQ(textOf(callOne("format", "si", {handle("%.1f%%"), 3})), "3.0%");
  EXPECT_EQ(textOf(callOne("format", "st",
                           {handle("(%g)"), floatBits(1), floatBits(0.5f), floatBits(2)})),
            "(1 0.5 2)");
}

TEST(Strings, SubstrAndGetcharFollowOsl) {
  int32_t s = handle("tile_03_2");
  EXPECT_EQ(textOf(callOne("substr", "sii", {s, 5, 2})), "03");
  EXPECT_EQ(textOf(callOne("substr", "si", {s, 5})), "03_2");
  EXPECT_EQ(textOf(callOne("substr", "sii", {s, -3, 2})), "3_"); // from the end
  EXPECT_EQ(textOf(callOne("substr", "sii", {s, 20, 2})), "");
  EXPECT_EQ(callOne("getchar", "si", {s, 0}), 't');
  EXPECT_EQ(callOne("getchar", "si", {s, 9}), 0);
  EXPECT_EQ(callOne("getchar", "si", {s, -1}), 0);
}

TEST(Strings, NumbersParseAPrefix) {
  EXPECT_EQ(callOne("stoi", "s", {handle("03")}), 3);
  EXPECT_EQ(callOne("stoi", "s", {handle("-12abc")}), -12);
  EXPECT_EQ(callOne("stoi", "s", {handle("abc")}), 0);
  EXPECT_EQ(callOne("stof", "s", {handle("-2.25x")}), floatBits(-2.25f));
}

TEST(Strings, PrefixSuffixAndRegex) {
  int32_t s = handle("tile_10_3");
  EXPECT_EQ(callOne("startswith", "ss", {s, handle("tile_1")}), 1);
  EXPECT_EQ(callOne("endswith", "ss", {s, handle("_3")}), 1);
  EXPECT_EQ(callOne("endswith", "ss", {handle("3"), handle("_3")}), 0);
  EXPECT_EQ(callOne("regex_search", "ss", {s, handle("_1[01]_")}), 1);
  EXPECT_EQ(callOne("regex_match", "ss", {s, handle("_1[01]_")}), 0);
  EXPECT_EQ(callOne("regex_match", "ss", {s, handle("tile_1[01]_[0-9]")}), 1);
}

TEST(Strings, BadRegexIsReportedAndGivesZero) {
  int before = osl::stringErrors();
  EXPECT_EQ(callOne("regex_search", "ss", {handle("a"), handle("(a")}), 0);
  EXPECT_EQ(osl::stringErrors(), before + 1);
  EXPECT_NE(osl::regexError("(a"), "");
  EXPECT_EQ(osl::regexError("a+"), "");
}

TEST(Strings, FormatErrorsAreFoundBeforeRunning) {
  EXPECT_EQ(osl::formatError("%s_%02d", "si"), "");
  EXPECT_NE(osl::formatError("%d %d", "i"), "");
  EXPECT_NE(osl::formatError("%d", "s"), "");
  EXPECT_NE(osl::formatError("50%", ""), "");
}

/// The pure functions the front end folds with give what the runtime gives
/// on handles, with no intern table.
TEST(Strings, PureFunctionsMatchTheRuntime) {
  auto value = [](char kind, std::string_view s, int32_t i = 0) {
    osl::StringValue v;
    v.kind = kind;
    v.s = s;
    v.i = i;
    return v;
  };
  std::string error;
  osl::StringResult r = osl::evalStringFunction(
      osl::stringFunctionCode("substr"), {value('s', "tile_12.tx"), value('i', "", -5)}, error);
  EXPECT_EQ(r.text, "12.tx");
  EXPECT_EQ(error, "");
  EXPECT_EQ(textOf(callOne("substr", "si", {handle("tile_12.tx"), -5})), r.text);
  osl::StringValue n = value('f', "");
  n.f[0] = 0.5f;
  r = osl::evalStringFunction(osl::stringFunctionCode("format"),
                              {value('s', "%s_%g"), value('s', "a"), n}, error);
  EXPECT_EQ(r.text, "a_0.5");
  r = osl::evalStringFunction(osl::stringFunctionCode("hash"), {value('s', "tile")}, error);
  EXPECT_EQ(r.bits, callOne("hash", "s", {handle("tile")}));
  // regex_search(subject, results, regex): entry 2 is where group 1 begins.
  r = osl::evalStringFunction(osl::stringFunctionCode("regex:result"),
                              {value('s', "tile_12"), value('s', "_([0-9]+)"), value('i', "", 0),
                               value('i', "", 2), value('i', "", -7)},
                              error);
  EXPECT_EQ(r.bits, 5);
  r = osl::evalStringFunction(osl::stringFunctionCode("regex_match"),
                              {value('s', "a"), value('s', "(a")}, error);
  EXPECT_NE(error, "");
  EXPECT_EQ(r.bits, 0);
}

TEST(Strings, OnlyMaskedLanesRun) {
  // strlen over 4 lanes, lanes 1 and 3 active.
  int32_t rows[8] = {handle("a"), handle("bb"), handle("ccc"), handle("dddd"), -1, -1, -1, -1};
  osl_rt_string_call("test", osl::stringFunctionCode("strlen"), "s", rows, 4, 0b1010);
  EXPECT_EQ(rows[4], 0);
  EXPECT_EQ(rows[5], 2);
  EXPECT_EQ(rows[6], 0);
  EXPECT_EQ(rows[7], 4);
}

TEST(Strings, ConcurrentInterningGivesOneHandlePerString) {
  std::vector<std::vector<int32_t>> seen(4);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&seen, t] {
      for (int i = 0; i < 2000; ++i)
        seen[t].push_back(handle(("s" + std::to_string(i)).c_str()));
    });
  for (std::thread &th : threads)
    th.join();
  for (int t = 1; t < 4; ++t)
    EXPECT_EQ(seen[t], seen[0]);
}

} // namespace
