// Medit .sol tensors (SolAtVertices, type 3): round trips, MMG layouts, malformed inputs.
#include <random>

#include <gtest/gtest.h>

#include "medit_test_meshes.h"
#include "rvor/medit.h"
#include "support/temp_dir.h"

namespace rvor::test {
namespace {

std::vector<Mat3> random_spd_tensors(int dimension, int count) {
  std::mt19937 random(12345);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Mat3> tensors;
  for (int i = 0; i < count; ++i) {
    Mat3 A = Mat3::NullaryExpr([&](Eigen::Index, Eigen::Index) { return uniform(random); });
    if (dimension == 2) A.row(2).setZero(), A.col(2).setZero();
    Mat3 G = A * A.transpose() + 0.1 * Mat3::Identity();
    G = (0.5 * (G + G.transpose())).eval();  // bit-exact symmetry: the file holds one triangle
    if (dimension == 2) G(2, 2) = 1.0;
    tensors.push_back(G);
  }
  return tensors;
}

void expect_round_trip(int dimension) {
  TempDir dir;
  const std::vector<Mat3> tensors = random_spd_tensors(dimension, 50);
  write_medit_sol_tensors(dir.file("m.sol"), dimension, tensors);
  const std::vector<Mat3> read = read_medit_sol_tensors(dir.file("m.sol"), 50);
  ASSERT_EQ(read.size(), tensors.size());
  for (std::size_t i = 0; i < tensors.size(); ++i)
    EXPECT_EQ(read[i], tensors[i]) << "vertex " << i;  // bit-exact
}

TEST(MeditSol, RoundTrip2D) {
  expect_round_trip(2);
}
TEST(MeditSol, RoundTrip3D) {
  expect_round_trip(3);
}

TEST(MeditSol, Writes2DTensorsAsThreeValues) {
  TempDir dir;
  Mat3 G = Mat3::Identity();
  G(0, 0) = 4, G(0, 1) = G(1, 0) = 0.5, G(1, 1) = 2;
  write_medit_sol_tensors(dir.file("m.sol"), 2, {G});
  EXPECT_NE(read_text(dir.file("m.sol")).find("SolAtVertices\n1\n1 3\n4 0.5 2\n"),
            std::string::npos)
      << read_text(dir.file("m.sol"));
}

TEST(MeditSol, UsesTheMeditComponentOrder) {
  TempDir dir;
  write_text(dir.file("m.sol"),
             "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n1\n1 3\n"
             "10 1 20 2 3 30\nEnd\n");
  Mat3 expected;
  expected << 10, 1, 2, 1, 20, 3, 2, 3, 30;
  EXPECT_EQ(read_medit_sol_tensors(dir.file("m.sol")).at(0), expected);
}

TEST(MeditSol, AcceptsMmgLayoutsAndSeveralFields) {
  TempDir dir;
  // Keywords and counts on one line, the type line split, a scalar field before the tensor.
  write_text(dir.file("m.sol"),
             "MeshVersionFormatted 2 Dimension 2\n# MMG style\nSolAtVertices 2\n2\n1\n3\n"
             "7 1 0 1\n8 2 0 2\nEnd\n");
  const std::vector<Mat3> tensors = read_medit_sol_tensors(dir.file("m.sol"), 2);
  ASSERT_EQ(tensors.size(), 2u);
  EXPECT_EQ(tensors[1](0, 0), 2);
  EXPECT_EQ(tensors[1](1, 1), 2);
  EXPECT_EQ(tensors[1](2, 2), 1);
}

void expect_sol_error(const std::string& text, int expected_vertices, int line,
                      const std::string& problem) {
  TempDir dir;
  const std::string path = dir.file("bad.sol");
  write_text(path, text);
  const std::string message =
      error_message([&] { read_medit_sol_tensors(path, expected_vertices); });
  EXPECT_NE(message.find(path + ":" + std::to_string(line) + ": "), std::string::npos) << message;
  EXPECT_NE(message.find(problem), std::string::npos) << message;
}

const char* const kSolHeader3D = "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n";  // 1-3

TEST(MeditSolErrors, MissingFile) {
  const std::string message = error_message([] { read_medit_sol_tensors("/nonexistent/m.sol"); });
  EXPECT_NE(message.find("cannot read Medit file /nonexistent/m.sol: No such file"),
            std::string::npos)
      << message;
}

TEST(MeditSolErrors, DirectoryInsteadOfAFile) {
  const std::string message = error_message([] { read_medit_sol_tensors("/tmp"); });
  EXPECT_NE(message.find("cannot read Medit file /tmp: it is a directory"), std::string::npos)
      << message;
}

TEST(MeditSolErrors, UnsupportedFormatVersion) {
  // As in a .mesh: the version was read and ignored, 9 or -5 accepted.
  for (const char* version : {"0", "-5", "9"})
    expect_sol_error(std::string("MeshVersionFormatted ") + version +
                         "\nDimension 3\nSolAtVertices\n1\n1 3\n1 0 1 0 0 1\n",
                     -1, 1, "unsupported MeshVersionFormatted " + std::string(version));
}

TEST(MeditSolErrors, ABinaryTokenIsQuotedShortAndEscaped) {
  const std::string token = "\x01" + std::string(3000, 'z');
  expect_sol_error(std::string(kSolHeader3D) + token + "\n", -1, 4, "'\\x01zzz");
  TempDir dir;
  write_text(dir.file("long.sol"), std::string(kSolHeader3D) + token + "\n");
  EXPECT_LT(error_message([&] { read_medit_sol_tensors(dir.file("long.sol")); }).size(), 300u);
}

TEST(MeditSolErrors, ScalarSolution) {
  expect_sol_error(std::string(kSolHeader3D) + "2\n1 1\n1\n2\nEnd\n", 2, 5,
                   "expected a tensor (type 3)");
}

TEST(MeditSolErrors, UnknownSolutionType) {
  expect_sol_error(std::string(kSolHeader3D) + "2\n1 9\n", 2, 5, "unknown solution type 9");
}

TEST(MeditSolErrors, CountDifferentFromTheMesh) {
  expect_sol_error(std::string(kSolHeader3D) + "2\n1 3\n1 0 1 0 0 1\n1 0 1 0 0 1\n", 3, 4,
                   "SolAtVertices has 2 entries but the mesh has 3 vertices");
}

TEST(MeditSolErrors, TruncatedData) {
  expect_sol_error(std::string(kSolHeader3D) + "2\n1 3\n1 0 1 0 0 1\n1 0 1\n", 2, 7,
                   "truncated file: it ends where solution 2 of 2");
}

TEST(MeditSolErrors, NanComponent) {
  expect_sol_error(std::string(kSolHeader3D) + "2\n1 3\n1 0 1 0 0 1\n1 0 NaN 0 0 1\n", -1, 7,
                   "tensor of vertex 2 (1-based) is not finite");
}

TEST(MeditSolErrors, TensorThatIsNotPositiveDefinite) {
  expect_sol_error(std::string(kSolHeader3D) + "3\n1 3\n1 0 1 0 0 1\n1 0 1 0 0 1\n1 2 1 0 0 1\n", 3,
                   8, "tensor of vertex 3 (1-based) is not symmetric positive definite");
}

TEST(MeditSolErrors, NoSolAtVerticesSection) {
  expect_sol_error("MeshVersionFormatted 2\nDimension 3\nSolAtTriangles\n1\n1 1\n5\nEnd\n", -1, 7,
                   "End before any SolAtVertices section");
}

// A 2D file whose lines hold 3D tensors: read as 2D, each line would give a vertex and a half.
TEST(MeditSolErrors, MoreValuesThanTheDimensionGives) {
  expect_sol_error(
      "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n2\n1 3\n4 1 2 3 0.5 1\n4 1 2 3 0.5 "
      "1\nEnd\n",
      2, 7, "unexpected value '4' after the SolAtVertices entries");
  expect_sol_error(std::string(kSolHeader3D) + "1\n1 3\n1 0 1 0 0 1\n1 2 3 garbage\n", 1, 7,
                   "unexpected value '1' after the SolAtVertices entries");
}

TEST(MeditSolErrors, SectionsAfterTheTensorsAreSkippedUpToEnd) {
  TempDir dir;
  write_text(dir.file("m.sol"),
             std::string(kSolHeader3D) + "1\n1 3\n2 0 1 0 0 1\nCorners\n1\n1\nEnd\n1 2 3\n");
  EXPECT_EQ(read_medit_sol_tensors(dir.file("m.sol")).size(), 1u);
}

TEST(MeditSolErrors, BinaryFileIsNamedAsSuch) {
  TempDir dir;
  write_text(dir.file("m.solb"), std::string("\x01\0\0\0\x02\0\0\0", 8));
  const std::string message = error_message([&] { read_medit_sol_tensors(dir.file("m.solb")); });
  EXPECT_NE(message.find("binary Medit .meshb/.solb is not supported"), std::string::npos)
      << message;
}

TEST(MeditSolErrors, MissingDimension) {
  expect_sol_error("MeshVersionFormatted 2\nSolAtVertices\n1\n1 3\n1 0 1 0 0 1\n", -1, 2,
                   "missing Dimension");
}

}  // namespace
}  // namespace rvor::test
