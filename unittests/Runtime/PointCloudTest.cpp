//===- PointCloudTest.cpp - kd-tree search and .geo files
//------------------===//
#include "OslRuntime/PointCloud.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <random>

using namespace osl;

namespace {

/// The answer PointKdTree::nearest must give, from every point.
void bruteForce(const std::vector<float> &p, const float c[3], float radius, int32_t maxPoints,
                std::vector<int32_t> &indices, std::vector<float> &d2) {
  std::vector<std::pair<float, int32_t>> all;
  for (size_t i = 0; i < p.size() / 3; ++i) {
    float dx = c[0] - p[3 * i], dy = c[1] - p[3 * i + 1], dz = c[2] - p[3 * i + 2];
    float dd = dx * dx + dy * dy + dz * dz;
    if (dd < radius * radius)
      all.push_back({dd, int32_t(i)});
  }
  std::sort(all.begin(), all.end());
  all.resize(std::min(all.size(), size_t(std::max(maxPoints, 0))));
  indices.clear();
  d2.clear();
  for (auto &[dd, i] : all)
    indices.push_back(i), d2.push_back(dd);
}

TEST(PointKdTree, MatchesSearchingEveryPoint) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  // Random points, and a grid whose equal distances test the tie order.
  std::vector<float> points;
  for (int i = 0; i < 500; ++i)
    for (int k = 0; k < 3; ++k)
      points.push_back(unit(random));
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x)
      points.insert(points.end(), {x / 9.0f, y / 9.0f, 0.5f});
  PointKdTree tree(points);
  std::vector<int32_t> got, want;
  std::vector<float> gotD, wantD;
  for (int q = 0; q < 400; ++q) {
    float c[3] = {unit(random), unit(random), q % 2 ? 0.5f : unit(random)};
    if (q % 5 == 0) // exactly on a grid point
      c[0] = float(q % 10) / 9.0f, c[1] = float(q / 10 % 10) / 9.0f, c[2] = 0.5f;
    float radius = 0.05f + 0.3f * unit(random);
    int32_t maxPoints = 1 + q % 17;
    int32_t n = tree.nearest(c, radius, maxPoints, got, gotD);
    bruteForce(points, c, radius, maxPoints, want, wantD);
    ASSERT_EQ(size_t(n), want.size()) << "query " << q;
    EXPECT_EQ(got, want) << "query " << q;
    EXPECT_EQ(gotD, wantD) << "query " << q;
  }
}

TEST(PointKdTree, NothingForBadQueries) {
  std::vector<float> points = {0, 0, 0, 1, 0, 0};
  PointKdTree tree(points);
  std::vector<int32_t> idx;
  std::vector<float> d2;
  float origin[3] = {0, 0, 0}, nan[3] = {NAN, 0, 0};
  EXPECT_EQ(tree.nearest(origin, 2, 0, idx, d2), 0);
  EXPECT_EQ(tree.nearest(origin, 0, 5, idx, d2), 0);
  EXPECT_EQ(tree.nearest(origin, NAN, 5, idx, d2), 0);
  EXPECT_EQ(tree.nearest(nan, 2, 5, idx, d2), 0);
  EXPECT_EQ(tree.nearest(origin, 2, 5, idx, d2), 2);
  std::vector<float> none;
  EXPECT_EQ(PointKdTree(none).nearest(origin, 2, 5, idx, d2), 0);
}

int32_t bits(float f) {
  int32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

TEST(GeoFile, WritesAndReadsBackEveryValue) {
  PointCloudData cloud;
  PointAttribute position{"position", 'f', 3, true, {}, {}};
  PointAttribute weight{"weight", 'f', 1, false, {}, {}};
  PointAttribute id{"id", 'i', 1, false, {}, {}};
  PointAttribute tag{"tag", 's', 1, false, {}, {"a", "bb"}};
  for (int p = 0; p < 3; ++p) {
    for (float v : {0.1f * p, 1.0f / 3.0f, -2.5e-7f * p})
      position.words.push_back(bits(v));
    weight.words.push_back(bits(1.0f / (p + 3)));
    id.words.push_back(-p);
    tag.words.push_back(p % 2);
  }
  cloud.attributes = {position, weight, id, tag};
  std::string path = testing::TempDir() + "pointcloud_test.geo", error;
  ASSERT_TRUE(writeGeoFile(path, cloud, error)) << error;
  PointCloudData back;
  ASSERT_TRUE(readGeoFile(path, back, error)) << error;
  ASSERT_EQ(back.size(), 3u);
  ASSERT_EQ(back.attributes.size(), 4u);
  for (size_t a = 0; a < 4; ++a) {
    EXPECT_EQ(back.attributes[a].name, cloud.attributes[a].name);
    EXPECT_EQ(back.attributes[a].oslKind(), cloud.attributes[a].oslKind());
    EXPECT_EQ(back.attributes[a].words, cloud.attributes[a].words) << cloud.attributes[a].name;
  }
  EXPECT_EQ(back.find("tag")->strings, (std::vector<std::string>{"a", "bb"}));
  std::remove(path.c_str());
}

TEST(GeoFile, ReportsWhatIsWrong) {
  std::string path = testing::TempDir() + "pointcloud_bad.geo", error;
  PointCloudData cloud;
  EXPECT_FALSE(readGeoFile(path + ".missing", cloud, error));
  EXPECT_NE(error.find("cannot read"), std::string::npos) << error;
  for (const char *text : {"not a geo file\n", "PGEOMETRY V5\nNPoints 2 NPrims 0\n",
                           "PGEOMETRY V5\nNPoints 2 NPrims 0\nNPointGroups 0 NPrimGroups 0\n"
                           "NPointAttrib 0 NVertexAttrib 0 NPrimAttrib 0 NAttrib 0\n0 0 0 1\n0 "
                           "0\n",
                           "PGEOMETRY V5\nNPoints 1 NPrims 0\nNPointGroups 0 NPrimGroups 0\n"
                           "NPointAttrib 1 NVertexAttrib 0 NPrimAttrib 0 NAttrib 0\nPointAttrib\n"
                           "m 16 matrix 0\n0 0 0 1 (0)\n"}) {
    FILE *f = std::fopen(path.c_str(), "w");
    ASSERT_TRUE(f);
    std::fputs(text, f);
    std::fclose(f);
    error.clear();
    EXPECT_FALSE(readGeoFile(path, cloud, error)) << text;
    EXPECT_NE(error.find("is not a point cloud"), std::string::npos) << error;
  }
  std::remove(path.c_str());
}

} // namespace
