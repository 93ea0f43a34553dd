//===- PointCloud.h - Point clouds: files, search, and the host side -*- C++
//-*-===//
//
// What pointcloud_search, pointcloud_get and pointcloud_write read and
// write: clouds of points with named attributes, kept as Houdini's ASCII
// geometry (.geo, "PGEOMETRY V5"), the format OSL's testshade writes through
// Partio. A cloud is read once per process and searched with a kd-tree.
// Written points are kept until the run ends (savePointClouds), in point
// order whatever the threads did.
//
//===----------------------------------------------------------------------===//
#ifndef OSLRUNTIME_POINTCLOUD_H
#define OSLRUNTIME_POINTCLOUD_H

#include <cstdint>
#include <string>
#include <vector>

namespace osl {

/// One attribute of every point: `components` 32-bit words per point (a
/// float's bits, an int, or an index into `strings`).
struct PointAttribute {
  std::string name;
  /// 'f' float, 'i' int, 's' string (words index `strings`).
  char type = 'f';
  /// 1, or 3 for a triple.
  int32_t components = 1;
  /// Houdini's name for a 3-float attribute: "vector" or "float".
  bool isVector = false;
  std::vector<int32_t> words;
  std::vector<std::string> strings;

  /// The OSL element kind it fills (i f t s), or 0 for none.
  char oslKind() const;
};

/// The points and their attributes. "position" is always the first
/// attribute once a cloud is read.
struct PointCloudData {
  std::vector<PointAttribute> attributes;
  size_t size() const { return attributes.empty() ? 0 : attributes[0].words.size() / 3; }
  const PointAttribute *find(const std::string &name) const;
};

/// Reads `path` (ASCII .geo); false with `error` on failure.
bool readGeoFile(const std::string &path, PointCloudData &cloud, std::string &error);
/// Writes `cloud` to `path` as ASCII .geo; false with `error` on failure.
bool writeGeoFile(const std::string &path, const PointCloudData &cloud, std::string &error);

/// A balanced kd-tree over a cloud's positions.
class PointKdTree {
public:
  explicit PointKdTree(const std::vector<float> &positions);
  /// Up to `maxPoints` points nearest `center` strictly within `radius`,
  /// nearest first (equal distances by index): their indices and squared
  /// distances. Returns how many.
  int32_t nearest(const float center[3], float radius, int32_t maxPoints,
                  std::vector<int32_t> &indices, std::vector<float> &distance2) const;

private:
  struct Found {
    float distance2;
    int32_t index;
  };
  void build(int32_t begin, int32_t end);
  void search(int32_t begin, int32_t end, const float center[3], std::vector<Found> &heap,
              size_t maxPoints, float &limit2) const;
  const std::vector<float> &positions;
  /// Point indices in tree order: a node is the middle of its range.
  std::vector<int32_t> order;
  /// The split axis of the node at each middle.
  std::vector<uint8_t> axis;
};

/// The first point of the batch this thread shades next: pointcloud_write
/// orders its points by it.
void setPointCloudBatch(long firstPoint);

/// How many point-cloud files could not be read (each counted once): a run
/// that needed one fails, as one that needed a missing texture does.
int pointCloudFileErrors();

/// Writes every cloud pointcloud_write made in this process. False with
/// `error` if one could not be written.
bool savePointClouds(std::string &error);

} // namespace osl

#endif // OSLRUNTIME_POINTCLOUD_H
