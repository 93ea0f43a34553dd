//===- osl-make-volume.cpp - Write a test volume for texture3d ------------===//
//
//   osl-make-volume OUT.vdb [N]
//
// Writes an OpenVDB file of N^3 voxels (default 16) of size 1/N covering
// world [0,1)^3, with two grids whose values are linear in the voxel's
// world position, so that trilinear interpolation reproduces them exactly
// and a texture3d lookup has a known answer:
//   "position" (Vec3): the voxel's world position (i, j, k) / N
//   "ramp"     (float): x + 2 y + 4 z of that position
//
//===----------------------------------------------------------------------===//
#include <openvdb/openvdb.h>

#include <cstdio>
#include <cstdlib>
#include <exception>

int main(int argc, char **argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: osl-make-volume OUT.vdb [N]\n");
    return 2;
  }
  int n = argc == 3 ? std::atoi(argv[2]) : 16;
  if (n < 2 || n > 256) {
    std::fprintf(stderr, "osl-make-volume: N must be 2 to 256\n");
    return 2;
  }
  try {
    openvdb::initialize();
    auto transform = openvdb::math::Transform::createLinearTransform(1.0 / n);
    auto position = openvdb::Vec3fGrid::create(openvdb::Vec3f(0.0f));
    auto ramp = openvdb::FloatGrid::create(0.0f);
    position->setName("position");
    ramp->setName("ramp");
    position->setTransform(transform);
    ramp->setTransform(transform->copy());
    auto positions = position->getAccessor();
    auto ramps = ramp->getAccessor();
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          openvdb::Vec3f p(float(i) / n, float(j) / n, float(k) / n);
          positions.setValue(openvdb::Coord(i, j, k), p);
          ramps.setValue(openvdb::Coord(i, j, k), p.x() + 2 * p.y() + 4 * p.z());
        }
    openvdb::GridPtrVec grids = {position, ramp};
    openvdb::io::File(argv[1]).write(grids);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "osl-make-volume: cannot write '%s': %s\n", argv[1], e.what());
    return 1;
  }
  return 0;
}
