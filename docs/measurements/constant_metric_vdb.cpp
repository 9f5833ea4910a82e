// Writes a metric .vdb of six constant grids m11 ... m33 (the identity tensor) over the unit
// cube, EDGE^3 voxels as leaves (no tiles), through OpenVDB's own writer: a small file that
// decompresses to many times its size. docs/measurements/vdb_guard.sh builds and uses it:
//   c++ -O1 -std=c++17 docs/measurements/constant_metric_vdb.cpp -o /tmp/constant_metric_vdb \
//       -lopenvdb -ltbb -lImath-3_1
//   /tmp/constant_metric_vdb FILE.vdb EDGE
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s FILE.vdb EDGE\n", argv[0]);
    return 2;
  }
  const int edge = std::stoi(argv[2]);
  openvdb::initialize();
  openvdb::GridPtrVec grids;
  const char* names[6] = {"m11", "m12", "m22", "m13", "m23", "m33"};
  for (int n = 0; n < 6; ++n) {
    auto grid = openvdb::FloatGrid::create(0.0f);
    grid->setName(names[n]);
    const bool diagonal = n == 0 || n == 2 || n == 5;
    grid->tree().denseFill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(edge - 1)),
                           diagonal ? 1.0f : 0.0f, true);
    grid->setTransform(openvdb::math::Transform::createLinearTransform(1.0 / edge));
    grids.push_back(grid);
  }
  openvdb::io::File(argv[1]).write(grids);
  return 0;
}
