// Medit .mesh reading and writing: round trips, files as MMG and Gmsh write them, and one test
// per kind of malformed input, each checking that the message names the file and the line.
#include <gtest/gtest.h>

#include "medit_test_meshes.h"
#include "rvor/medit.h"
#include "support/temp_dir.h"

namespace rvor::test {
namespace {

void expect_same_mesh(const MeditMesh& expected, const MeditMesh& actual) {
  EXPECT_EQ(expected.dimension, actual.dimension);
  ASSERT_EQ(expected.vertices.size(), actual.vertices.size());
  for (std::size_t i = 0; i < expected.vertices.size(); ++i)
    EXPECT_EQ(expected.vertices[i], actual.vertices[i]) << "vertex " << i;  // bit-exact
  EXPECT_EQ(expected.edges, actual.edges);
  EXPECT_EQ(expected.triangles, actual.triangles);
  EXPECT_EQ(expected.tetrahedra, actual.tetrahedra);
  EXPECT_EQ(expected.edge_refs, actual.edge_refs);
  EXPECT_EQ(expected.triangle_refs, actual.triangle_refs);
  EXPECT_EQ(expected.tetrahedron_refs, actual.tetrahedron_refs);
}

TEST(MeditMesh, RoundTrip3DKeepsCoordinatesBitExactAndRefs) {
  TempDir dir;
  MeditMesh mesh = unit_cube_tetrahedra(2);
  mesh.vertices[1] += Vec3(0.1, 1e-300, -1.0 / 3.0);  // values without a short decimal form
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t) mesh.tetrahedron_refs[t] = int(t) - 7;
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  mesh.triangle_refs = {10, -2};
  mesh.edges = {{0, 26}};
  mesh.edge_refs = {3};
  write_medit_mesh(dir.file("cube.mesh"), mesh);
  expect_same_mesh(mesh, read_medit_mesh(dir.file("cube.mesh")));
}

TEST(MeditMesh, RoundTrip2DWritesTwoCoordinatesPerVertex) {
  TempDir dir;
  MeditMesh mesh = unit_square_triangles(3);
  mesh.edges = {{0, 1}, {1, 2}};
  mesh.edge_refs = {5, 6};
  write_medit_mesh(dir.file("square.mesh"), mesh);
  const std::string text = read_text(dir.file("square.mesh"));
  EXPECT_NE(text.find("Dimension 2"), std::string::npos);
  EXPECT_NE(text.find("Vertices\n16\n0 0 0\n"), std::string::npos) << text.substr(0, 80);
  expect_same_mesh(mesh, read_medit_mesh(dir.file("square.mesh")));
}

TEST(MeditMesh, MissingRefsAreWrittenAsZero) {
  TempDir dir;
  MeditMesh mesh = unit_cube_tetrahedra(1);
  mesh.tetrahedron_refs.clear();
  write_medit_mesh(dir.file("a.mesh"), mesh);
  EXPECT_EQ(read_medit_mesh(dir.file("a.mesh")).tetrahedron_refs, std::vector<int>(6, 0));
}

TEST(MeditMesh, WriteRejectsOutOfRangeIndicesAndKeepsNoFile) {
  TempDir dir;
  MeditMesh mesh = unit_cube_tetrahedra(1);
  mesh.tetrahedra[0][2] = 8;
  const std::string message = error_message([&] { write_medit_mesh(dir.file("a.mesh"), mesh); });
  EXPECT_NE(message.find(dir.file("a.mesh")), std::string::npos) << message;
  EXPECT_NE(message.find("out of range"), std::string::npos) << message;
}

TEST(MeditMesh, ReadsFilesWithCommentsOddLayoutAndSectionsItDoesNotUse) {
  TempDir dir;
  write_text(dir.file("mmg.mesh"),
             "# written by hand in the style of MMG and Gmsh\n"
             "MeshVersionFormatted\n 2\n\nDimension\n3\n"
             "Vertices\n4\n"
             "0 0 0 1\n1 0 0 1   # a comment after values\n0 1 0 1\n0 0 1 2\n"
             "Corners 2\n1\n2\n"
             "RequiredVertices\n1\n3\n"
             "Ridges\n1\n1\n"
             "Normals\n2\n0 0 1\n1 0 0\n"
             "NormalAtVertices\n2\n1 1\n2 2\n"
             "Quadrilaterals 1\n1 2 3 4 0\n"
             "SomethingNew 3\n1 2\n3 4\n5 6\n"
             "Edges 1\n1 2 7\n"
             "Triangles\n2\n1 2 3 4\n1 2 4 5\n"
             "Tetrahedra 1 1 2 3 4 9\n"
             "End\n"
             "anything after End is ignored\n");
  const MeditMesh mesh = read_medit_mesh(dir.file("mmg.mesh"));
  EXPECT_EQ(mesh.dimension, 3);
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.vertices[3], Vec3(0, 0, 1));
  EXPECT_EQ(mesh.edges, (std::vector<std::array<int, 2>>{{0, 1}}));
  EXPECT_EQ(mesh.edge_refs, std::vector<int>{7});
  EXPECT_EQ(mesh.triangles, (std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 1, 3}}));
  EXPECT_EQ(mesh.triangle_refs, (std::vector<int>{4, 5}));
  EXPECT_EQ(mesh.tetrahedra, (std::vector<std::array<int, 4>>{{0, 1, 2, 3}}));
  EXPECT_EQ(mesh.tetrahedron_refs, std::vector<int>{9});
}

TEST(MeditMesh, Reads2DVerticesWithTwoCoordinates) {
  TempDir dir;
  write_text(dir.file("tri.mesh"),
             "MeshVersionFormatted 1\nDimension 2\nVertices\n3\n0 0 1\n2.5 0 1\n0 1e-1 3\n"
             "Triangles\n1\n1 2 3 0\nEnd\n");
  const MeditMesh mesh = read_medit_mesh(dir.file("tri.mesh"));
  EXPECT_EQ(mesh.dimension, 2);
  EXPECT_EQ(mesh.vertices[1], Vec3(2.5, 0, 0));
  EXPECT_EQ(mesh.vertices[2], Vec3(0, 0.1, 0));
}

// A UTF-8 byte order mark before the first keyword, as some Windows editors write: it made the
// first token unknown, and the file was refused.
TEST(MeditMesh, SkipsAByteOrderMark) {
  TempDir dir;
  write_text(dir.file("bom.mesh"),
             "\xEF\xBB\xBFMeshVersionFormatted 1\nDimension 2\nVertices\n3\n0 0 1\n2.5 0 1\n"
             "0 1 3\nTriangles\n1\n1 2 3 0\nEnd\n");
  const MeditMesh mesh = read_medit_mesh(dir.file("bom.mesh"));
  EXPECT_EQ(mesh.vertices.size(), 3u);
  EXPECT_EQ(mesh.triangles.size(), 1u);
}

// The message of reading `text` as a .mesh must start with "FILE:LINE:" and hold `problem`.
void expect_read_error(const std::string& text, int line, const std::string& problem) {
  TempDir dir;
  const std::string path = dir.file("bad.mesh");
  write_text(path, text);
  const std::string message = error_message([&] { read_medit_mesh(path); });
  EXPECT_EQ(message.rfind(path + ":" + std::to_string(line) + ": ", 0), 0u) << message;
  EXPECT_NE(message.find(problem), std::string::npos) << message;
}

const char* const kHeader3D = "MeshVersionFormatted 2\nDimension 3\n";  // lines 1-2

TEST(MeditMeshErrors, MissingFileNamesThePath) {
  const std::string message = error_message([] { read_medit_mesh("/nonexistent/dir/x.mesh"); });
  EXPECT_NE(message.find("/nonexistent/dir/x.mesh"), std::string::npos) << message;
  EXPECT_NE(message.find("cannot read Medit file"), std::string::npos) << message;
}

TEST(MeditMeshErrors, VerticesBeforeDimension) {
  expect_read_error("MeshVersionFormatted 2\n\nVertices\n1\n0 0 0 0\nEnd\n", 3,
                    "missing Dimension");
}

TEST(MeditMeshErrors, NoDimensionAtAll) {
  expect_read_error("MeshVersionFormatted 2\n", 1, "missing Dimension");
}

TEST(MeditMeshErrors, UnknownDimension) {
  expect_read_error("MeshVersionFormatted 2\nDimension 4\n", 2, "unknown dimension 4");
}

TEST(MeditMeshErrors, VerticesTruncatedByEndOfFile) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n3\n0 0 0 0\n1 0 0 0\n", 6, "truncated");
}

TEST(MeditMeshErrors, VerticesTruncatedByTheNextSection) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n3\n0 0 0 0\n1 0 0 0\nTriangles\n0\n", 7,
                    "truncated section: found 'Triangles' where vertex 3 of 3");
}

TEST(MeditMeshErrors, TetrahedraTruncatedInTheMiddleOfALine) {
  expect_read_error(std::string(kHeader3D) +
                        "Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
                        "Tetrahedra\n2\n1 2 3 4 0\n1 2\nEnd\n",
                    13, "element 2 of 2 in the Tetrahedra section");
}

TEST(MeditMeshErrors, NonNumericCoordinate) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n2\n0 0 0 0\n1 0x1 0 0\n", 6,
                    "'0x1' is not a number (vertex 2 of 2 in the Vertices section)");
}

TEST(MeditMeshErrors, WordWhereACoordinateBelongs) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n2\n0 0 0 0\n1 zero 0 0\n", 6,
                    "'zero' is not a number (vertex 2 of 2 in the Vertices section)");
}

TEST(MeditMeshErrors, TwoSignsBeforeACoordinate) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n2\n0 0 0 0\n1 +-1 0 0\n", 6,
                    "'+-1' is not a number (vertex 2 of 2 in the Vertices section)");
}

TEST(MeditMeshErrors, NonIntegerVertexIndex) {
  expect_read_error(
      std::string(kHeader3D) + "Vertices\n3\n0 0 0 0\n1 0 0 0\n0 1 0 0\nTriangles\n1\n1 2.5 3 0\n",
      10, "'2.5' is not an integer");
}

TEST(MeditMeshErrors, NanCoordinate) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n2\n0 0 0 0\n1 nan 0 0\n", 6,
                    "coordinate 2 of vertex 2 is not finite");
}

TEST(MeditMeshErrors, OverflowingCoordinate) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n1\n0 0 -1e999 0\n", 5,
                    "coordinate 3 of vertex 1 is not finite");
}

TEST(MeditMeshErrors, VertexIndexBeyondTheVertexCount) {
  expect_read_error(std::string(kHeader3D) +
                        "Vertices\n3\n0 0 0 0\n1 0 0 0\n0 1 0 0\n"
                        "Triangles\n2\n1 2 3 0\n1 4 3 0\nEnd\n",
                    11, "vertex index 4 in the Triangles section is out of range");
}

TEST(MeditMeshErrors, VertexIndexBeyondTheVertexCountWhenElementsComeFirst) {
  expect_read_error(
      std::string(kHeader3D) + "Edges\n1\n1 5 0\nVertices\n3\n0 0 0 0\n1 0 0 0\n0 1 0 0\nEnd\n", 5,
      "vertex index 5 in the Edges section is out of range");
}

TEST(MeditMeshErrors, ZeroVertexIndex) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n1\n0 0 0 0\nEdges\n1\n0 1 0\n", 8,
                    "out of range (indices start at 1)");
}

TEST(MeditMeshErrors, NegativeCount) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n-2\n", 4, "invalid count -2");
}

TEST(MeditMeshErrors, NumberWhereAKeywordBelongs) {
  expect_read_error(std::string(kHeader3D) + "Vertices\n1\n0 0 0 0 7\n", 5,
                    "expected a section keyword, found '7'");
}

}  // namespace
}  // namespace rvor::test
