// Bad input through the real tool: each case must end with exit code 1 (not a crash), exactly one
// line on stderr that names the problem and where, and no output file left behind.
#include <algorithm>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "rvor/devices.h"
#include "rvor/spec_text.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

namespace rvor::test {
namespace {

class CliErrors : public ::testing::Test {
 protected:
  TempDir dir;
  std::string out() const { return dir.file("out"); }

  // A valid small 2D run; tests replace one piece of it.
  std::string voronoi(const std::string& args) const {
    return rvor_binary() + " voronoi --quiet --out " + out() + " " + args;
  }
  std::string seeds2d() const {
    write_text(dir.file("seeds.xyz"), "0.1 0.2\n-0.5 0.3\n");
    return dir.file("seeds.xyz");
  }
  // A one-triangle Medit mesh (m.mesh) and its metric (m.sol), the second vertex's tensor given.
  void write_one_triangle_metric(const std::string& second_tensor) const {
    write_text(dir.file("m.mesh"),
               "MeshVersionFormatted 2\nDimension 2\nVertices\n3\n0 0 0\n1 0 0\n0 1 "
               "0\nTriangles\n1\n1 2 3 0\nEnd\n");
    write_text(dir.file("m.sol"),
               "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n3\n1 3\n1 0 1\n" +
                   second_tensor + "\n1 0 1\nEnd\n");
  }

  void expect_error(const std::string& args, const std::string& fragment) const {
    const CommandResult result = run_command(voronoi(args));
    EXPECT_EQ(result.exit_code, 1) << "stderr: " << result.err;
    ASSERT_FALSE(result.err.empty());
    EXPECT_EQ(result.err.find('\n'), result.err.size() - 1) << "more than one line: " << result.err;
    EXPECT_NE(result.err.find("rvor: error: "), std::string::npos) << result.err;
    EXPECT_NE(result.err.find(fragment), std::string::npos)
        << "expected '" << fragment << "' in: " << result.err;
    EXPECT_FALSE(std::filesystem::exists(out() + "/voronoi.vdb"));
  }
};

// Without --quiet the stages print progress on stderr; an error in the middle of one must still
// start its own line, after the stage is marked failed.
TEST_F(CliErrors, ErrorDuringAStageStartsItsOwnLine) {
  const CommandResult result =
      run_command(rvor_binary() + " voronoi --out " + out() +
                  " --domain rect:-1,-1,1,1 --resolution 16 --metric swirly --seeds " + seeds2d());
  EXPECT_EQ(result.exit_code, 1) << "stderr: " << result.err;
  EXPECT_NE(result.err.find("building canvas ... failed\nrvor: error: "), std::string::npos)
      << result.err;
  EXPECT_EQ(result.err.back(), '\n') << result.err;
}

TEST_F(CliErrors, NonSpdUniformMetric) {
  expect_error(
      "--domain rect:-1,-1,1,1 --resolution 16 --metric uniform:1,2,1 --seeds " + seeds2d(),
      "not symmetric positive definite");
}

TEST_F(CliErrors, NanUniformMetric) {
  expect_error(
      "--domain rect:-1,-1,1,1 --resolution 16 --metric uniform:nan,0,1 --seeds " + seeds2d(),
      "uniform");
}

TEST_F(CliErrors, UnknownMetricName) {
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --metric swirly --seeds " + seeds2d(),
               "swirly");
}

TEST_F(CliErrors, MalformedSeedFile) {
  write_text(dir.file("bad.xyz"), "0.1 0.2\n0.3 zero\n");
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + dir.file("bad.xyz"),
               "bad.xyz:2");
}

// Empty fields between separators are no numbers ("0.1,,0.2" was read as 2D "0.1 0.2"); control
// bytes are shown escaped; a UTF-8 byte order mark before the first line is skipped.
TEST_F(CliErrors, SeedFilesWithEmptyFieldsOrControlBytes) {
  for (const char* line : {"0.1,,0.2\n", ",0.1,0.2\n", "0.1,0.2,\n", "0.1;;0.2\n"}) {
    write_text(dir.file("fields.xyz"), std::string("0 0\n") + line);
    expect_error("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + dir.file("fields.xyz"),
                 "fields.xyz:2: expected 2 or 3 finite numbers");
  }
  write_text(dir.file("control.xyz"), "0.1 0.2\x01\n");
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + dir.file("control.xyz"),
               "got '0.1 0.2\\x01'");
  write_text(dir.file("bom.xyz"),
             "\xEF\xBB\xBF"
             "0.1 0.2\n-0.5 0.3\n");
  const CommandResult result = run_command(
      voronoi("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + dir.file("bom.xyz")));
  EXPECT_EQ(result.exit_code, 0) << result.err;
}

// A seed file with classic Mac OS line ends (CR alone), once refused as one malformed line, or a
// mix of line ends and a comment, gives the same two seeds (the line ends themselves:
// InputLines.EndAtLfCrlfOrALoneCr).
TEST_F(CliErrors, SeedFilesReadWithAnyLineEnds) {
  for (const char* text : {"0.1 0.2\r0.3 0.4\r", "# two seeds\r0.1 0.2\n\r0.3 0.4\r\n"}) {
    SCOPED_TRACE(quoted_text(text));
    write_text(dir.file("ends.xyz"), text);
    const CommandResult result = run_command(voronoi(
        "--overwrite --domain rect:-1,-1,1,1 --resolution 16 --seeds " + dir.file("ends.xyz")));
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_EQ(read_text(out() + "/seeds.xyz"), "0.1 0.2\n0.3 0.4\n");
  }
}

// A line separates its numbers by blanks, by commas or by semicolons, one kind spaced alike: a
// decimal comma read as a separator gave another point ("0.5 0,5", "1;2,5" and "0.5, 0,5" were
// all read as 3D points).
TEST_F(CliErrors, ASeedLineWhoseCommaMayBeADecimalOneIsRefused) {
  const std::string domain = "--domain box:-10,-10,-10,10,10,10 --resolution 16 --seeds ";
  for (const char* line : {"0.5 0,5\n", "1;2,5\n", "0.5, 0,5\n", "2,5;0\n"}) {
    write_text(dir.file("comma.xyz"), std::string("1 2 3\n") + line);
    expect_error(domain + dir.file("comma.xyz"), "comma.xyz:2: expected 2 or 3 finite numbers");
  }
  write_text(dir.file("spaced.xyz"), "1, 2, 3\n-1 ; 2 ; 2.5\n1,2,3\n1;2;3\n");
  const CommandResult result = run_command(voronoi(domain + dir.file("spaced.xyz")));
  EXPECT_EQ(result.exit_code, 0) << result.err;
}

// A failing read (here EIO: the process's own memory at address 0) names the file; the stream's
// exception said only "basic_filebuf::underflow error reading the file".
TEST_F(CliErrors, AReadErrorNamesTheFile) {
  if (!std::filesystem::exists("/proc/self/mem")) GTEST_SKIP() << "no /proc/self/mem";
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --seeds /proc/self/mem",
               "cannot read /proc/self/mem at line 1: ");
}

TEST_F(CliErrors, EmptySeedFile) {
  write_text(dir.file("empty.xyz"), "# nothing\n");
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + dir.file("empty.xyz"),
               "no points");
}

TEST_F(CliErrors, SeedOutsideDomain) {
  write_text(dir.file("far.xyz"), "0 0\n# a comment\n5 5\n");
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + dir.file("far.xyz"),
               "far.xyz:3: seed 1 at (5, 5, 0) is outside the domain");
}

// An empty file name (an unset shell variable) used to mean "not given": --metric-vdb '' ran
// with the default Euclidean metric.
TEST_F(CliErrors, EmptyFileNamesAreRefused) {
  for (const std::string option :
       {"--metric-vdb", "--metric-mesh", "--metric-file", "--seeds", "--probe", "--out"})
    expect_error("--domain rect:-1,-1,1,1 --resolution 16 --random-seeds 2 " + option + " ''",
                 option + ": an empty path");
}

TEST_F(CliErrors, EmptyDomain) {
  expect_error("--domain box:0,0,0,0,1,1 --resolution 16 --random-seeds 3", "box:0,0,0,0,1,1");
}

// A box or rectangle thinner than half a voxel has no voxel centre inside it: the canvas held one
// layer of voxels outside the domain, and seeds drawn there.
TEST_F(CliErrors, BoxThinnerThanHalfAVoxel) {
  expect_error("--domain rect:0,0,100,1 --resolution 32 --random-seeds 3", "thinner than a voxel");
  expect_error("--domain box:0,0,0,100,100,1 --resolution 32 --random-seeds 3",
               "thinner than a voxel");
}

// Files without line ends (a binary file, /dev/zero) are refused at their first MiB, not read
// whole into memory first (/dev/zero ran until the memory was gone).
TEST_F(CliErrors, TextInputsWithoutLineEndsAreRefusedEarly) {
  write_text(dir.file("long.xyz"), std::string((1 << 20) + 10, '1'));
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + dir.file("long.xyz"),
               "long.xyz:1: a line longer than 1 MiB");
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --seeds /dev/zero",
               "/dev/zero:1: a line longer than 1 MiB");
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --random-seeds 2 --probe /dev/zero",
               "/dev/zero:1: a line longer");
  std::filesystem::create_symlink("/dev/zero", dir.file("zero.off"));
  expect_error("--domain mesh:" + dir.file("zero.off") + " --resolution 16 --random-seeds 2",
               "zero.off:1: a line longer");
  expect_error(
      "--domain rect:0,0,1,1 --resolution 16 --metric-mesh /dev/zero --metric-file "
      "/dev/zero --random-seeds 2",
      "/dev/zero: a binary file");
}

// A FIFO that nothing writes to blocked the run in its open, silently and for ever: the run now
// says that it waits, and reads the FIFO once a writer comes.
TEST_F(CliErrors, AFifoInputWithoutAWriterIsAnnounced) {
  const std::string fifo = dir.file("fifo.xyz");
  ASSERT_EQ(run_command("mkfifo " + fifo).exit_code, 0);
  for (const std::string option : {"--seeds", "--probe"}) {
    SCOPED_TRACE(option);
    const std::string err = dir.file("err.txt");
    const std::string seeds = option == "--seeds" ? "" : " --random-seeds 2";
    const std::string script = "(" +
                               voronoi("--overwrite --domain rect:-1,-1,1,1 --resolution 16 " +
                                       option + " " + fifo + seeds) +
                               " 2>" + err + " & pid=$!; for i in $(seq 100); do grep -q waiting " +
                               err +
                               " && break; sleep 0.1; done; printf '0.1 0.2\\n-0.5 0.3\\n' >" +
                               fifo + "; wait $pid; echo $?)";
    const CommandResult result = run_command(script);
    EXPECT_EQ(result.out, "0\n") << read_text(err);
    EXPECT_EQ(read_text(err), "rvor: waiting for point file " + fifo +
                                  ", a FIFO that nothing has written to yet\n");
  }
}

// A run interrupted by SIGTERM, SIGINT or SIGHUP (`timeout`, Ctrl-C, a closed terminal) removes
// its staging directory, and the output directory and the folders above it that it created
// (those were left), before it dies of the signal; they stayed until a later run into the same
// --out. `timeout` signals the process and then its group,
// whose second signal once killed the process while another thread cleaned. (SIGINT is left out
// here: a shell's background job ignores it, and rvor keeps a signal its caller ignores.)
TEST_F(CliErrors, InterruptedRunLeavesNoStagingBehind) {
  struct Case {
    const char* name;
    int number;
  };
  for (const Case signal : {Case{"TERM", 15}, Case{"HUP", 1}}) {
    const std::string parent = dir.file(std::string("interrupted-") + signal.name);
    std::filesystem::create_directories(parent);
    const std::string out_dir = parent + "/made/out";
    // A CPU solve of seconds, signalled once its staging directory is there.
    const std::string script =
        "(" + rvor_binary() + " voronoi --quiet --device cpu --domain box:1,1,1,11,11,11 " +
        "--metric radial_shock_3d --resolution 160 --random-seeds 50 --out " + out_dir +
        " & pid=$!; for i in $(seq 100); do ls -a " + out_dir +
        " 2>/dev/null | grep -q outputs && break; sleep 0.1; done; sleep 0.3; kill -" +
        signal.name + " $pid; wait $pid; echo $?)";
    const CommandResult result = run_command(script);
    EXPECT_EQ(result.out, std::to_string(128 + signal.number) + "\n")
        << signal.name << ": " << result.err;
    EXPECT_FALSE(std::filesystem::exists(parent + "/made")) << signal.name;
    EXPECT_TRUE(std::filesystem::exists(parent)) << "a directory the run did not create";
  }
}

// A hangup the caller ignores (nohup) stays ignored on the OpenCL device too: PoCL's LLVM puts its
// own handlers in SIG_IGN's place when OpenCL starts, and the run died of the terminal's SIGHUP
// (exit 129). A signal that does stop a run ends its open progress line with "interrupted".
TEST_F(CliErrors, AnIgnoredHangupStaysIgnoredAndAnInterruptEndsTheLine) {
  if (list_opencl_devices().empty()) GTEST_SKIP() << "no OpenCL device";
  const std::string run = rvor_binary() +
                          " voronoi --device pocl --domain box:1,1,1,11,11,11 --metric "
                          "radial_shock_3d --resolution 160 --random-seeds 1000 --out ";
  const auto signalled = [&](const std::string& out_dir, const std::string& ignore,
                             const std::string& signal) {
    return "(" + ignore + run + out_dir + " >/dev/null 2>" + out_dir +
           ".err & pid=$!; for i in $(seq 100); do grep -q propagating " + out_dir +
           ".err 2>/dev/null && break; sleep 0.1; done; kill -" + signal +
           " $pid; wait $pid; echo $?)";
  };
  const std::string ignored = dir.file("ignored");
  const CommandResult kept = run_command(signalled(ignored, "trap '' HUP; ", "HUP"));
  EXPECT_EQ(kept.out, "0\n") << read_text(ignored + ".err");
  EXPECT_TRUE(std::filesystem::exists(ignored + "/voronoi.vdb"));
  const std::string stopped = dir.file("stopped");
  const CommandResult ended = run_command(signalled(stopped, "", "TERM"));
  EXPECT_EQ(ended.out, "143\n");
  const std::string err = read_text(stopped + ".err");
  EXPECT_NE(err.find("propagating from 1000 seeds ... interrupted\n"), std::string::npos) << err;
}

// A run that fails removes the output directory it created (an empty directory was left).
TEST_F(CliErrors, FailedRunRemovesTheOutputDirectoryItCreated) {
  ASSERT_FALSE(std::filesystem::exists(out()));
  expect_error("--domain rect:-1,-1,1,1 --resolution 4 --random-seeds 100", "16 active voxels");
  EXPECT_FALSE(std::filesystem::exists(out()));
  std::filesystem::create_directory(out());
  expect_error("--domain rect:-1,-1,1,1 --resolution 4 --random-seeds 100", "16 active voxels");
  EXPECT_TRUE(std::filesystem::exists(out())) << "a directory the run did not create";
}

// Its parents too, where it created them (they were left behind), but no folder that was there.
TEST_F(CliErrors, FailedRunRemovesTheFoldersItCreatedAboveTheOutputDirectory) {
  const std::string args = "--quiet --domain rect:-1,-1,1,1 --metric bogus --random-seeds 3 --out ";
  EXPECT_EQ(run_command(rvor_binary() + " voronoi " + args + dir.file("n1/n2/n3/")).exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir.file("n1")));
  // Folders the path names on its way, beyond where it ends.
  EXPECT_EQ(run_command(rvor_binary() + " voronoi " + args + dir.file("new/./n/../out")).exit_code,
            1);
  EXPECT_FALSE(std::filesystem::exists(dir.file("new")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("out")));
  std::filesystem::create_directories(dir.file("kept/a"));
  write_text(dir.file("kept/a/file"), "mine");
  EXPECT_EQ(run_command(rvor_binary() + " voronoi " + args + dir.file("kept/a/b/c")).exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir.file("kept/a/b")));
  EXPECT_EQ(read_text(dir.file("kept/a/file")), "mine");
}

// A bad value is reported before the outputs are looked at: it came after "... already exists",
// and only --overwrite, which replaces the earlier results, showed it. So are bad specs, input
// files, the canvas's memory estimate and the seeds' places on the canvas; the earlier outputs
// stay.
TEST_F(CliErrors, BadValuesComeBeforeTheOutputsChecks) {
  const std::string args = "--domain rect:-1,-1,1,1 --resolution 8 --random-seeds 3";
  ASSERT_EQ(run_command(voronoi(args)).exit_code, 0);
  const std::string report = read_text(out() + "/report.json");
  write_text(dir.file("nan.xyz"), "0.1 0.2\nnan 0.3\n");
  write_text(dir.file("far.xyz"), "0.1 0.2\n5 5\n");
  write_text(dir.file("bad-probe.xyz"), "hello world\n");
  const std::string rect = "--domain rect:-1,-1,1,1 --resolution 16 ";
  for (const auto& [more, fragment] : std::vector<std::pair<std::string, std::string>>{
           {args + " --memory-budget 12Q", "--memory-budget: memory budget '12Q' is not"},
           {args + " --seeds " + seeds2d(), "give either --seeds or --random-seeds, not both"},
           {"--domain rect:garbage --random-seeds 2", "malformed domain 'rect:garbage'"},
           {"--domain implicit:cube --random-seeds 2", "cube"},
           {"--domain box:0,0,0,0,1,1 --random-seeds 2", "box:0,0,0,0,1,1"},
           {rect + "--random-seeds 2 --metric bogus", "bogus"},
           {rect + "--random-seeds 2 --metric uniform:1,2,1", "not symmetric positive definite"},
           {rect + "--seeds /nonexistent", "cannot read point file /nonexistent"},
           {rect + "--seeds " + dir.file("nan.xyz"), "nan.xyz:2: expected 2 or 3 finite numbers"},
           {rect + "--seeds " + dir.file("far.xyz"), "far.xyz:2: seed 1 at (5, 5, 0) is outside"},
           {rect + "--random-seeds 2 --probe " + dir.file("bad-probe.xyz"), "bad-probe.xyz:1"},
           {"--domain box:-1,-1,-1,1,1,1 --resolution 16 --random-seeds 2 --png", "--png"},
           {rect + "--random-seeds 2 --memory-budget 1K", "over the memory budget of 1 KiB"},
           {"--domain rect:-1,-1,1,1 --resolution 4 --random-seeds 200", "16 active voxels"}}) {
    SCOPED_TRACE(more);
    const CommandResult result = run_command(voronoi(more));
    EXPECT_EQ(result.exit_code, 1);
    EXPECT_NE(result.err.find(fragment), std::string::npos) << result.err;
    EXPECT_EQ(read_text(out() + "/report.json"), report);
  }
}

// A budget past what rvor represents is positive: it was called "not a positive size".
TEST_F(CliErrors, AMemoryBudgetTooLargeIsCalledSo) {
  for (const std::string size : {"18446744073709551615", "1e30", "16777216T"}) {
    const CommandResult result =
        run_command(voronoi("--domain rect:-1,-1,1,1 --random-seeds 3 --memory-budget " + size));
    EXPECT_EQ(result.exit_code, 1);
    EXPECT_NE(result.err.find("memory budget '" + size +
                              "' is beyond the largest size rvor can represent"),
              std::string::npos)
        << result.err;
  }
}

// Control characters the user gave (a spec, $RVOR_DEVICE, a path) are shown as \xNN in the
// error line, as a seed file's bytes are: an escape sequence reached the terminal raw and acted
// there (clearing the screen, colouring the rest). UTF-8 is kept.
TEST_F(CliErrors, ControlCharactersOfTheCommandLineAreShownEscaped) {
  const CommandResult domain =
      run_command(voronoi("--random-seeds 3 --domain \"$(printf 'rect:\\033[2J-1,-1,1,1')\""));
  const CommandResult device = run_command("RVOR_DEVICE=\"$(printf 'x\\033[31mred')\" " +
                                           voronoi("--domain rect:-1,-1,1,1 --random-seeds 3"));
  const CommandResult listed =
      run_command("RVOR_DEVICE=\"$(printf 'x\\033[31mred')\" " + rvor_binary() + " devices");
  const CommandResult path = run_command(
      voronoi("--domain rect:-1,-1,1,1 --seeds \"$(printf 'no\\302\\233such-\\303\\251.xyz')\""));
  for (const CommandResult& result : {domain, device, path}) {
    EXPECT_EQ(result.exit_code, 1);
    EXPECT_EQ(result.err.find('\x1B'), std::string::npos) << result.err;
    EXPECT_EQ(result.err.find('\n'), result.err.size() - 1) << result.err;
  }
  EXPECT_NE(domain.err.find("'rect:\\x1B[2J-1,-1,1,1'"), std::string::npos) << domain.err;
  EXPECT_NE(device.err.find("RVOR_DEVICE=x\\x1B[31mred"), std::string::npos) << device.err;
  EXPECT_EQ(listed.out.find('\x1B'), std::string::npos) << listed.out;
  // A C1 control (U+009B, the 8-bit CSI) escaped by its bytes; an accent kept.
  EXPECT_NE(path.err.find("no\\xC2\\x9Bsuch-\xC3\xA9.xyz"), std::string::npos) << path.err;
}

// A scale whose square overflows double said "is not finite: [inf -nan inf ...]" (0 * inf); it
// overflows float, as a smaller one past float's range is said to.
TEST_F(CliErrors, AScaleWhoseSquareOverflowsIsNamed) {
  expect_error("--domain rect:-1,-1,1,1 --random-seeds 2 --metric euclidean:scale=1e300",
               "metric euclidean: scale 1e+300 overflows float");
  expect_error(
      "--domain box:-1,-1,-1,1,1,1 --random-seeds 2 --metric uniform:1,0,1,0,0,1,scale=1e160",
      "metric uniform: scale 1e+160 overflows float");
  expect_error("--domain rect:-1,-1,1,1 --random-seeds 2 --metric euclidean:scale=1e20",
               "does not fit in float");
}

TEST_F(CliErrors, ZeroResolution) {
  expect_error("--domain rect:-1,-1,1,1 --resolution 0 --seeds " + seeds2d(), "resolution");
}

TEST_F(CliErrors, AbsurdResolutionIsRefusedByTheMemoryEstimate) {
  expect_error("--domain box:-1,-1,-1,1,1,1 --resolution 60000 --random-seeds 3", "memory budget");
}

TEST_F(CliErrors, MemoryBudgetOverride) {
  expect_error("--domain box:-1,-1,-1,1,1,1 --resolution 64 --memory-budget 1M --random-seeds 3",
               "memory budget");
}

// The curved dual keeps a field per seed over its star box (radial_shock_3d at 192^3 with 2000
// seeds: 46 box voxels per canvas voxel, so ~25 GB of floats at 512^3) and solves them a few at a
// time: where one solve does not fit beside the canvas it is refused before solving, and where
// only some fit, fewer run at once.
TEST_F(CliErrors, CurvedDualWhoseLocalFieldsDoNotFitIsRefused) {
  const std::string args =
      "--domain box:-1,-1,-1,1,1,1 --resolution 32 --random-seeds 5 --dual curved --memory-budget ";
  expect_error(args + "7M", "curved dual: the seeds' local fields need");
  // Sizes are shown in the budget's binary units (7M said "7.34 MB"); suffixes in either case.
  expect_error(args + "7M", "over the memory budget of 7 MiB (--memory-budget)");
  expect_error(args + "7m", "over the memory budget of 7 MiB (--memory-budget)");
  const CommandResult fits = run_command(voronoi(args + "12M"));  // one solve at a time
  EXPECT_EQ(fits.exit_code, 0) << fits.err;
  EXPECT_TRUE(std::filesystem::exists(out() + "/curved_faces.vtu"));
}

// bench takes --memory-budget as voronoi does (its refusals named an option it did not have), for
// the canvas and for the CPU reference, whose refusal says how to skip it.
TEST_F(CliErrors, BenchTakesAMemoryBudget) {
  const std::string bench = rvor_binary() +
                            " bench --quiet --domain rect:-1,-1,1,1 --resolution 64 --seeds 3 "
                            "--no-fastsweeping --memory-budget ";
  const CommandResult canvas = run_command(bench + "100K");
  EXPECT_EQ(canvas.exit_code, 1);
  EXPECT_NE(canvas.err.find("canvas of ~4096 active voxels needs ~192 KiB, over the memory budget "
                            "of 100 KiB (--memory-budget)"),
            std::string::npos)
      << canvas.err;
  const CommandResult reference = run_command(bench + "400K");
  EXPECT_EQ(reference.exit_code, 1);
  EXPECT_NE(reference.err.find("over the memory budget of 400 KiB"), std::string::npos)
      << reference.err;
  EXPECT_NE(reference.err.find("--no-reference skips it"), std::string::npos) << reference.err;
  EXPECT_EQ(run_command(bench + "400K --no-reference").exit_code, 0);
}

// A tensor whose Selling offsets pass what the engines store (int8) is refused by both with its
// position and why: the OpenCL engine named a slot index and advised refining, which cannot help
// (offsets do not depend on the resolution), and the reference gave neither. Anisotropy 1e4.
TEST_F(CliErrors, StencilOffsetsPastWhatTheEnginesStoreAreNamed) {
  for (const char* device : {"cpu", "pocl"}) {
    if (std::string(device) == "pocl" && list_opencl_devices().empty()) continue;
    expect_error(std::string("--device ") + device +
                     " --domain rect:-1,-1,1,1 --resolution 16 --random-seeds 3 --metric "
                     "uniform:20574944.93148327,40424819.7867313,79425056.06851673",
                 "canvas voxel (0, 0, 0) at (-0.9375, -0.9375, 0): metric [20574944 40424820 "
                 "40424820 79425056] is too anisotropic for rvor's stencils: its Selling stencil "
                 "has an offset of 167 voxels along x, past the 127 either engine stores");
  }
}

// One seed makes no element, which is not a failed triangulation ("NOT a triangulation, 0
// elements" said so).
TEST_F(CliErrors, ADualOfTooFewSeedsSaysWhyItHasNoElements) {
  write_text(dir.file("one.xyz"), "0.1 0.2\n");
  const CommandResult result = run_command(
      rvor_binary() + " voronoi --out " + out() +
      " --domain rect:-1,-1,1,1 --resolution 16 --dual straight --seeds " + dir.file("one.xyz"));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("(no elements: 1 seed, and a triangle needs 3)"), std::string::npos)
      << result.err;
}

// Seeds all on one point, line (2D) or plane (3D) make no element either, and say why ("NOT a
// triangulation, 0 elements" said nothing of it).
TEST_F(CliErrors, ADualOfDegenerateSeedsSaysWhyItHasNoElements) {
  struct Case {
    std::string domain, seeds, detail;
  };
  for (const Case& c : {Case{"rect:-1,-1,1,1", "0 0\n0.5 0\n-0.5 0\n",
                             "(no elements: the 3 seeds are collinear, and a triangle needs 3 "
                             "seeds off one line)"},
                        Case{"rect:-1,-1,1,1", "0.1 0.1\n0.1 0.1\n0.1 0.1\n",
                             "(no elements: the 3 seeds are all at one point"},
                        Case{"box:-1,-1,-1,1,1,1", "0 0 0\n0.5 0 0\n0 0.5 0\n0.5 0.5 0\n",
                             "(no elements: the 4 seeds are coplanar, and a tetrahedron needs 4 "
                             "seeds off one plane)"}}) {
    SCOPED_TRACE(c.seeds);
    write_text(dir.file("flat.xyz"), c.seeds);
    const CommandResult result =
        run_command(rvor_binary() + " voronoi --overwrite --out " + out() + " --domain " +
                    c.domain + " --resolution 16 --dual straight --seeds " + dir.file("flat.xyz"));
    EXPECT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.err.find(c.detail), std::string::npos) << result.err;
  }
}

// A domain too thin for most Voronoi vertices leaves most seeds in no element: the progress line
// says how many ("a triangulation, 1 elements" of 60 seeds said nothing of the 56 left out).
TEST_F(CliErrors, ADualThatLeavesSeedsOutSaysHowMany) {
  const CommandResult result =
      run_command(rvor_binary() + " voronoi --device cpu --out " + out() +
                  " --domain box:0,0,0,1,1,0.02 --resolution 96 --random-seeds 60 --dual straight");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  const auto report = nlohmann::json::parse(read_text(out() + "/report.json"));
  const std::size_t unused = report["dual"]["unused_vertices"];
  const std::size_t elements = report["dual"]["tetrahedra"];
  ASSERT_GT(unused, 30u);
  ASSERT_GT(elements, 0u);
  EXPECT_NE(
      result.err.find(std::to_string(elements) + (elements == 1 ? " element, " : " elements, ") +
                      std::to_string(unused) + " of the 60 seeds in none)"),
      std::string::npos)
      << result.err;
}

// The curved dual's progress line tells unreached edges from unreached faces: seeds at the box's
// corners leave faces whose geodesics run along its faces unreached, and "14 geodesic edges, 9
// faces, 2 unreached" did not say which.
TEST_F(CliErrors, CurvedDualNamesUnreachedEdgesAndFacesApart) {
  write_text(dir.file("corners.xyz"),
             "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n1 1 0\n0.5 0.5 0.5\n0.3 0.7 0.2\n");
  const CommandResult result = run_command(
      rvor_binary() + " voronoi --device cpu --out " + out() +
      " --domain box:0,0,0,1,1,1 --resolution 48 --dual curved --seeds " + dir.file("corners.xyz"));
  EXPECT_EQ(result.exit_code, 0) << result.err;
  const auto curved = nlohmann::json::parse(read_text(out() + "/report.json"))["curved_dual"];
  const std::size_t faces = curved["faces"], unreached_faces = curved["unreached_faces"];
  ASSERT_GT(unreached_faces, 0u);
  EXPECT_NE(
      result.err.find(std::to_string(curved["edges"].get<std::size_t>()) + " geodesic edges (" +
                      std::to_string(curved["unreached_edges"].get<std::size_t>()) +
                      " unreached), " + std::to_string(faces) + " faces (" +
                      std::to_string(unreached_faces) + " unreached))"),
      std::string::npos)
      << result.err;
}

TEST_F(CliErrors, MalformedDomain) {
  expect_error("--domain box:1,2,3 --resolution 16 --random-seeds 3", "box:1,2,3");
}

// A shape's parameter is checked by its name before its value: "axis=z" said "'z' is not a
// finite number", "foo=bar" "'bar' is not...", as if the names were right.
TEST_F(CliErrors, AnUnknownShapeParameterIsNamedBeforeItsValueIsRead) {
  expect_error("--domain implicit:torus:axis=z --resolution 16 --random-seeds 3",
               "unknown parameter 'axis' for shape 'torus' (known: center, R, r)");
  expect_error("--domain implicit:sphere:foo=bar --resolution 16 --random-seeds 3",
               "unknown parameter 'foo' for shape 'sphere' (known: center, r)");
  expect_error("--domain implicit:cube:foo=bar --resolution 16 --random-seeds 3",
               "unknown shape 'cube'");
  expect_error("--domain implicit:sphere:r=big --resolution 16 --random-seeds 3",
               "'big' is not a finite number");
}

TEST_F(CliErrors, TruncatedMeditMesh) {
  write_text(dir.file("m.mesh"),
             "MeshVersionFormatted 2\nDimension 2\nVertices\n3\n0 0 0\n1 0 0\n");
  write_text(
      dir.file("m.sol"),
      "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n3\n1 3\n1 0 1\n1 0 1\n1 0 1\nEnd\n");
  expect_error("--domain rect:0,0,1,1 --resolution 16 --metric-mesh " + dir.file("m.mesh") +
                   " --metric-file " + dir.file("m.sol") + " --seeds " + seeds2d(),
               "m.mesh");
}

TEST_F(CliErrors, NonSpdTensorInSol) {
  write_one_triangle_metric("1 5 1");
  expect_error("--domain rect:0,0,1,1 --resolution 16 --metric-mesh " + dir.file("m.mesh") +
                   " --metric-file " + dir.file("m.sol") + " --seeds " + seeds2d(),
               "m.sol");
}

// A .sol given to --metric-mesh (or a .mesh to --metric-file) failed with the reader's words
// only ("m.sol: no Tetrahedra to interpolate the metric on"): the error names what each takes.
TEST_F(CliErrors, SwappedMeditFilesAreNamedWithWhatEachOptionTakes) {
  write_one_triangle_metric("1 0 1");
  expect_error("--domain rect:0,0,1,1 --resolution 16 --metric-mesh " + dir.file("m.sol") +
                   " --metric-file " + dir.file("m.mesh") + " --seeds " + seeds2d(),
               "m.sol: no Triangles to interpolate the metric on (--metric-mesh "
               "takes the .mesh file, --metric-file the .sol file)");
}

// "--seeds 100" (a count, as rvor bench's --seeds takes) said "cannot read point file 100": the
// error names --random-seeds. A file that is named by a number is still read.
TEST_F(CliErrors, ASeedCountGivenToSeedsNamesRandomSeeds) {
  const std::string in_dir = "cd " + dir.path() + " && ";
  CommandResult result =
      run_command(in_dir + voronoi("--domain rect:-1,-1,1,1 --resolution 16 --seeds 100"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("rvor: error: --seeds 100: no such file; --seeds takes a file of "
                            "points, --random-seeds a count (for 100 random seeds: "
                            "--random-seeds 100)"),
            std::string::npos)
      << result.err;
  write_text(dir.file("100"), "0.1 0.2\n");
  result = run_command(in_dir + voronoi("--domain rect:-1,-1,1,1 --resolution 16 --seeds 100"));
  EXPECT_EQ(result.exit_code, 0) << result.err;
}

TEST_F(CliErrors, UnwritableOutputDirectory) {
  write_text(dir.file("a-file"), "not a directory");
  const CommandResult result =
      run_command(rvor_binary() + " voronoi --quiet --out " + dir.file("a-file") +
                  "/sub --domain rect:-1,-1,1,1 --resolution 16 --seeds " + seeds2d());
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("cannot write to output directory"), std::string::npos) << result.err;
}

TEST_F(CliErrors, ExistingOutputsAreNotReplacedWithoutOverwrite) {
  std::filesystem::create_directories(out());
  write_text(out() + "/report.json", "mine");
  const CommandResult result =
      run_command(voronoi("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + seeds2d()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("--overwrite"), std::string::npos) << result.err;
  EXPECT_EQ(read_text(out() + "/report.json"), "mine");
}

TEST_F(CliErrors, PngOf3DRun) {
  expect_error("--domain box:-1,-1,-1,1,1,1 --resolution 16 --random-seeds 3 --png", "--png");
  // The run created --out and left nothing in it: the directory goes too.
  EXPECT_FALSE(std::filesystem::exists(out()));
}

// Cairo draws no picture wider than 32767 pixels: a 2D canvas of 33000 voxels along x was solved
// and its outputs written, then the PNG failed ("cairo could not allocate") and took them all.
// It is refused with the inputs, before the solve and before --out is created.
TEST_F(CliErrors, PngWiderThanCairoDrawsIsRefusedBeforeTheSolve) {
  const CommandResult result = run_command(
      rvor_binary() + " voronoi --out " + out() +
      " --domain rect:0,0,100,0.1 --resolution 33000 --random-seeds 5 --device cpu --png");
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("building canvas ... failed\nrvor: error: --png: "), std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find("33000x33 pixels"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("32767"), std::string::npos) << result.err;
  EXPECT_EQ(result.err.find("propagating"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(out()));
}

TEST_F(CliErrors, UnknownDevice) {
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --device quantum --seeds " + seeds2d(),
               "quantum");
}

// A run that fails after some outputs could have been written (here the probe file) leaves an
// earlier run's outputs as they were, even with --overwrite: outputs move in together at the end.
TEST_F(CliErrors, FailingRunWithOverwriteKeepsTheEarlierOutputs) {
  ASSERT_EQ(run_command(voronoi("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + seeds2d()))
                .exit_code,
            0);
  const std::string report = read_text(out() + "/report.json");
  const std::string vdb = read_text(out() + "/voronoi.vdb");
  write_text(dir.file("bad.xyz"), "hello world\n");
  const CommandResult result =
      run_command(voronoi("--domain rect:-1,-1,1,1 --resolution 16 --random-seeds 3 --overwrite "
                          "--probe " +
                          dir.file("bad.xyz")));
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("bad.xyz:1"), std::string::npos) << result.err;
  EXPECT_EQ(read_text(out() + "/report.json"), report);
  EXPECT_EQ(read_text(out() + "/voronoi.vdb"), vdb);
  EXPECT_FALSE(std::filesystem::exists(out() + "/probe.csv"));
  for (const auto& entry : std::filesystem::directory_iterator(out()))  // no staging left
    EXPECT_NE(entry.path().filename().string()[0], '.') << entry.path();
}

TEST_F(CliErrors, OutputNameTakenByADirectory) {
  std::filesystem::create_directories(out() + "/report.json");
  const CommandResult result = run_command(
      voronoi("--domain rect:-1,-1,1,1 --resolution 16 --overwrite --seeds " + seeds2d()));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("is not a regular file"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(out() + "/voronoi.vdb"));
}

// Command-line parse errors follow the tool's rule too: one line, exit code 1.
TEST_F(CliErrors, ParseErrorsAreOneLineWithExitCodeOne) {
  const std::string tool = rvor_binary();
  for (const std::string& args :
       {std::string("voronoi --domain rect:-1,-1,1,1 --resolution abc"),
        std::string("voronoi --domain rect:-1,-1,1,1 --no-such-option"), std::string("frobnicate"),
        std::string(""), std::string("voronoi --domain rect:-1,-1,1,1 --random-seeds -1"),
        std::string("bench --insert -1"), std::string("bench --seeds 0"),
        std::string("bench --rng-seed 99999999999999999999"), std::string("bench --front-step nan"),
        // 2^64, which a comparison in double took for 2^64 - 1; a step the engine would refuse.
        std::string("bench --rng-seed 18446744073709551616"), std::string("bench --front-step 0.1"),
        std::string("bench --phase-iterations 0"), std::string("bench --insert-batch 0"),
        std::string("bench --insertion-phase-iterations 65"),
        // An option of the other variants' schedules, which this one would ignore.
        std::string("bench --variant brick_lanes --insertion-phase-iterations 2"),
        std::string("bench --variant voxel_phases --front-step 3"),
        std::string("bench --max-sweeps 0"), std::string("bench --max-sweeps 65"),
        std::string("bench --variant voxel_phases --max-sweeps 3"),
        // Options nothing in the run would read (each small enough to run quickly if taken).
        std::string("bench --resolution 8 --seeds 2 --no-fastsweeping --device cpu --variant "
                    "voxel_phases"),
        std::string("bench --resolution 8 --seeds 2 --no-fastsweeping --device cpu --front-step 3"),
        std::string("bench --resolution 8 --seeds 2 --no-fastsweeping --device cpu --max-sweeps 3"),
        std::string("bench --resolution 8 --seeds 2 --no-fastsweeping --insert-batch 2"),
        std::string("bench --resolution 8 --seeds 2 --no-fastsweeping --checked-insert"),
        std::string("voronoi --quiet --out " + out() +
                    " --domain rect:-1,-1,1,1 --resolution 8 "
                    "--seeds " +
                    seeds2d() + " --rng-seed 5"),
        // A variant by the number CLI11's mapping gave it.
        std::string("bench --resolution 8 --seeds 2 --no-fastsweeping --variant 2"),
        std::string("voronoi --quiet --domain rect:-1,-1,1,1 --random-seeds 3 --memory-budget 0.5"),
        std::string("voronoi --domain rect:-1,-1,1,1 --metric uniform:1,0,1 --metric-vdb m.vdb")}) {
    const CommandResult result = run_command(tool + " " + args);
    EXPECT_EQ(result.exit_code, 1) << args << ": " << result.err;
    ASSERT_FALSE(result.err.empty()) << args;
    EXPECT_EQ(result.err.find('\n'), result.err.size() - 1) << args << ": " << result.err;
    EXPECT_EQ(result.err.rfind("rvor: error: ", 0), 0u) << args << ": " << result.err;
  }
  EXPECT_NE(run_command(tool + " frobnicate").err.find("unknown sub-command 'frobnicate'"),
            std::string::npos);
  // An option before any sub-command is named (CLI11 said "A subcommand is required").
  EXPECT_NE(run_command(tool + " --frobnicate").err.find("unknown option '--frobnicate'"),
            std::string::npos);
  const CommandResult version = run_command(tool + " --version");
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out.rfind("rvor ", 0), 0u) << version.out;
}

// An option the command does not know is named with the one it was likely meant to be (CLI11
// said "The following arguments were not expected: 4 --rng-seeds", the words backwards, without
// a hint), and stray words come in the order they were typed.
TEST_F(CliErrors, AnUnknownOptionIsNamedWithTheOptionItWasLikelyMeantToBe) {
  const std::string tool = rvor_binary() + " ";
  const std::string run = "voronoi --domain rect:-1,-1,1,1 --random-seeds 3 ";
  for (const auto& [args, text] : std::vector<std::pair<std::string, std::string>>{
           {run + "--rng-seeds 4",
            "unknown option '--rng-seeds' for `rvor voronoi` (did you mean --rng-seed?)"},
           {run + "--output x", "(did you mean --out?)"},
           {run + "--metric_file m.sol", "(did you mean --metric-file?)"},
           {"bench --random-seeds 10",
            "unknown option '--random-seeds' for `rvor bench` (did "
            "you mean --seeds?)"},
           {"bench --resolutoin=8",
            "'--resolutoin=8' for `rvor bench` (did you mean "
            "--resolution?)"},
           {run + "--verbose", "unknown option '--verbose' for `rvor voronoi` (see"},
           {"--rng-seed 4 " + run, "option '--rng-seed' comes before the sub-command"},
           // After "--" an option's name is a word no option took, not one typed too early.
           {run + "-- --out x", "unexpected arguments '--out x --out "},
           {"voronoi --domain rect:-1 -1 1 1 --random-seeds 3",
            "unexpected arguments '-1 1 1': each option takes one value"}}) {
    const CommandResult result = run_command(tool + args + " --out " + out());
    EXPECT_EQ(result.exit_code, 1) << args;
    EXPECT_EQ(result.err.find('\n'), result.err.size() - 1) << args << ": " << result.err;
    EXPECT_NE(result.err.find(text), std::string::npos) << args << ": " << result.err;
  }
  EXPECT_FALSE(std::filesystem::exists(out()));
}

// An option given twice was "--metric: At Most 1 required but received 2", CLI11's words.
TEST_F(CliErrors, AnOptionGivenTwiceIsCalledSo) {
  const CommandResult result =
      run_command(rvor_binary() +
                  " voronoi --domain rect:-1,-1,1,1 --metric uniform:9,0,1 --metric euclidean " +
                  "--random-seeds 3 --out " + out());
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err,
            "rvor: error: --metric is given 2 times: give it once (see `rvor voronoi --help`)\n");
}

// Seed files must match the domain: one coordinate count on every line, 3 in 3D, z = 0 in 2D.
TEST_F(CliErrors, SeedFilesThatDoNotFitTheDomain) {
  struct Case {
    const char* domain;
    const char* seeds;
    const char* fragment;
  };
  for (const Case& c : {Case{"rect:-1,-1,1,1", "0 0 0\n0.1 0.2 0.5\n", "seeds.xyz:2: z = 0.5"},
                        Case{"box:-1,-1,-1,1,1,1", "0 0 0\n0.5 0.5\n", "seeds.xyz:2: 2 coord"},
                        Case{"box:-1,-1,-1,1,1,1", "0 0\n0.5 0.5\n", "the domain is 3D"}}) {
    write_text(dir.file("seeds.xyz"), c.seeds);
    expect_error(
        std::string("--domain ") + c.domain + " --resolution 16 --seeds " + dir.file("seeds.xyz"),
        c.fragment);
  }
}

// Whole numbers are decimal: CLI11 converts with base 0, so a leading zero made "010" octal 8.
TEST_F(CliErrors, WholeNumbersWithLeadingZerosAreDecimal) {
  const auto seeds_of = [&](const std::string& args) {
    const std::string out_dir = dir.file("seeds-" + std::to_string(std::hash<std::string>{}(args)));
    const CommandResult result =
        run_command(rvor_binary() + " voronoi --quiet --device cpu --out " + out_dir +
                    " --domain rect:-1,-1,1,1 " + args);
    EXPECT_EQ(result.exit_code, 0) << args << ": " << result.err;
    return read_text(out_dir + "/seeds.xyz");
  };
  EXPECT_EQ(seeds_of("--resolution 16 --random-seeds 010 --rng-seed 010"),
            seeds_of("--resolution 16 --random-seeds 10 --rng-seed 10"));
  EXPECT_NE(seeds_of("--resolution 16 --random-seeds 10 --rng-seed 010"),
            seeds_of("--resolution 16 --random-seeds 10 --rng-seed 8"));
  EXPECT_EQ(seeds_of("--resolution 016 --random-seeds 09 --rng-seed 09"),
            seeds_of("--resolution 16 --random-seeds 9 --rng-seed 9"));
}

// bench's counts too ("--repeat 010" ran 8 times, "--phase-iterations 0x10" 16), and a count out
// of format or range is named with the range the option takes (--resolution said "from
// -2147483648 to 2^31 - 1", then the canvas refused it).
TEST_F(CliErrors, CountsAreDecimalAndNamedWithTheirRange) {
  const std::string bench = rvor_binary() +
                            " bench --json --domain rect:-1,-1,1,1 --resolution 8 --seeds 2 "
                            "--no-reference --no-fastsweeping ";
  const CommandResult repeated = run_command(bench + "--repeat 010");
  EXPECT_EQ(repeated.exit_code, 0) << repeated.err;
  EXPECT_NE(repeated.out.find("\"repeat\": 10,"), std::string::npos) << repeated.out;
  for (const std::string& args : {std::string("--variant voxel_phases --phase-iterations 0x10"),
                                  std::string("--variant voxel_phases --phase-iterations 010.5"),
                                  std::string("--repeat 0x10")}) {
    const CommandResult result = run_command(bench + args);
    EXPECT_EQ(result.exit_code, 1) << args;
    EXPECT_NE(result.err.find("is not a whole number from 1 to "), std::string::npos) << result.err;
  }
  expect_error("--domain rect:-1,-1,1,1 --random-seeds 5 --resolution 1.5",
               "--resolution: '1.5' is not a whole number from 2 to 65536");
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --random-seeds 0",
               "--random-seeds: '0' is not a whole number from 1 to ");
}

// A seed file with more seeds than voxels (here 300 copies of one point on 256 voxels) is refused
// before the solve: the seed blocks' claims grew with the square of the seeds per voxel.
TEST_F(CliErrors, MoreSeedsInAFileThanVoxels) {
  std::string many;
  for (int n = 0; n < 300; ++n) many += "0.1 0.2\n";
  write_text(dir.file("many.xyz"), many);
  expect_error("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + dir.file("many.xyz"),
               "300 seeds on a canvas of 256 active voxels: at least 44 would share a voxel");
}

TEST_F(CliErrors, MoreRandomSeedsThanVoxels) {
  expect_error("--domain rect:-1,-1,1,1 --resolution 4 --random-seeds 100", "16 active voxels");
}

// Coordinates that double indices, float distances or OpenVDB transforms cannot hold are refused
// when the canvas is placed, not after the solve.
TEST_F(CliErrors, DomainScalesTheNumbersCannotHold) {
  expect_error("--domain rect:0,0,1e39,1e39 --resolution 16 --random-seeds 3", "beyond");
  // An extent past double's range (it was called empty or thinner than a voxel).
  expect_error("--domain box:-1e308,0,0,1e308,1,1 --resolution 16 --random-seeds 3",
               "has coordinates beyond +-1e+15");
  expect_error("--domain rect:0,0,1e-20,1e-20 --resolution 16 --random-seeds 3", "OpenVDB");
  expect_error("--domain box:1e14,0,0,100000000000001,1,1 --resolution 16 --random-seeds 3",
               "voxels from the origin");
}

// `rvor bench` takes its default device from $RVOR_DEVICE as `rvor voronoi` does, so a bad value
// is refused there too rather than silently replaced by auto.
TEST_F(CliErrors, BenchTakesTheDeviceFromTheEnvironment) {
  const CommandResult result =
      run_command("RVOR_DEVICE=quantum " + rvor_binary() +
                  " bench --quiet --metric euclidean --domain box:0,0,0,1,1,1 --resolution 8 "
                  "--seeds 2 --no-reference --no-fastsweeping");
  EXPECT_EQ(result.exit_code, 1) << "stderr: " << result.err;
  EXPECT_NE(result.err.find("RVOR_DEVICE=quantum: unknown device 'quantum'"), std::string::npos)
      << result.err;
}

// A device that does not exist gives one line (the devices found on the same line), saying that
// the name came from $RVOR_DEVICE; "opencl: 0" is not "opencl:0".
TEST_F(CliErrors, DeviceErrorsAreOneLineAndNameTheirSource) {
  const CommandResult from_environment =
      run_command("RVOR_DEVICE=opencl:99 " +
                  voronoi("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + seeds2d()));
  const CommandResult spaced = run_command(
      voronoi("--domain rect:-1,-1,1,1 --resolution 16 --device 'opencl: 0' --seeds " + seeds2d()));
  for (const CommandResult& result : {from_environment, spaced}) {
    EXPECT_EQ(result.exit_code, 1) << "stderr: " << result.err;
    EXPECT_EQ(result.err.find('\n'), result.err.size() - 1) << "more than one line: " << result.err;
  }
  EXPECT_NE(from_environment.err.find("RVOR_DEVICE=opencl:99: no OpenCL device matches"),
            std::string::npos)
      << from_environment.err;
  const CommandResult devices = run_command("RVOR_DEVICE=quantum " + rvor_binary() + " devices");
  EXPECT_NE(devices.out.find("but it cannot be used: unknown device 'quantum'"), std::string::npos)
      << devices.out;
  const CommandResult missing = run_command("RVOR_DEVICE=opencl:99 " + rvor_binary() + " devices");
  EXPECT_NE(missing.out.find("but it cannot be used: no OpenCL device matches"), std::string::npos)
      << missing.out;
}

// OpenVDB's file writer does not check its stream: a file size limit (or a full disk) used to
// leave a truncated voronoi.vdb, published with exit code 0.
TEST_F(CliErrors, TruncatedVdbFileIsAnError) {
  const CommandResult result = run_command(
      "ulimit -f 20; " + voronoi("--device cpu --domain rect:-1,-1,1,1 --resolution 32 --seeds " +
                                 seeds2d()));  // voronoi.vdb needs 28 KB, the limit is 20 KiB
  EXPECT_EQ(result.exit_code, 1) << "stderr: " << result.err;
  // Named as the output, not its staging path; SIGXFSZ (which would kill rvor) is ignored.
  EXPECT_NE(result.err.find("cannot write " + out() + "/voronoi.vdb: write failed"),
            std::string::npos)
      << result.err;
  EXPECT_FALSE(std::filesystem::exists(out() + "/voronoi.vdb"));
}

// PoCL aborts the process on an empty POCL_CACHE_DIR (an assertion, exit 134), lists no device when
// it cannot create the directory, and fails every build when the path is a file: each is one
// clear error naming POCL_CACHE_DIR. (No PoCL device: the others are not PoCL's to report.)
TEST_F(CliErrors, UnusablePoclCacheDirectoriesAreNamed) {
  const std::string file = dir.file("not-a-directory");
  write_text(file, "x\n");
  const CommandResult empty = run_command(
      "POCL_CACHE_DIR= " + voronoi("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + seeds2d()));
  EXPECT_EQ(empty.exit_code, 1) << "stderr: " << empty.err;
  EXPECT_NE(empty.err.find("POCL_CACHE_DIR is set but empty"), std::string::npos) << empty.err;
  if (list_opencl_devices().empty()) GTEST_SKIP() << "no OpenCL device";
  for (const std::string& path : {file, std::string("/proc/rvor-no-such-dir")}) {
    const CommandResult result =
        run_command("POCL_CACHE_DIR=" + path + " " +
                    voronoi("--domain rect:-1,-1,1,1 --resolution 16 --seeds " + seeds2d()));
    EXPECT_EQ(result.exit_code, 1) << "stderr: " << result.err;
    EXPECT_NE(result.err.find("POCL_CACHE_DIR=" + path + " is not a writable directory"),
              std::string::npos)
        << result.err;
  }
}

// Where POCL_CACHE_DIR is unset PoCL keeps its kernels under $XDG_CACHE_HOME or $HOME (a service
// account's /nonexistent, a file) and lists no device when it cannot make that directory; a stale
// POCL_DEVICES or OCL_ICD_VENDORS empties the list too. The error said only "devices found: none".
TEST_F(CliErrors, AnEmptyDeviceListNamesPoclsDefaultCacheAndTheDiscoveryVariables) {
  if (list_opencl_devices().empty()) GTEST_SKIP() << "no OpenCL device";
  const std::string file = dir.file("home-is-a-file");
  write_text(file, "x\n");
  const std::string run = voronoi("--domain rect:-1,-1,1,1 --resolution 16 --random-seeds 3");
  const CommandResult home =
      run_command("env -u POCL_CACHE_DIR -u XDG_CACHE_HOME HOME=" + file + " " + run);
  EXPECT_EQ(home.exit_code, 1) << "stderr: " << home.err;
  EXPECT_EQ(home.err.find('\n'), home.err.size() - 1) << "more than one line: " << home.err;
  EXPECT_NE(home.err.find("PoCL's kernel cache " + file +
                          "/.cache/pocl/kcache (from HOME) is not a writable directory"),
            std::string::npos)
      << home.err;
  EXPECT_NE(home.err.find("set POCL_CACHE_DIR to a writable directory"), std::string::npos)
      << home.err;
  const CommandResult xdg = run_command("env -u POCL_CACHE_DIR XDG_CACHE_HOME=" + file + " " + run);
  EXPECT_NE(xdg.err.find(file + "/pocl/kcache (from XDG_CACHE_HOME)"), std::string::npos)
      << xdg.err;
  const CommandResult devices = run_command("POCL_DEVICES=no-such-kind " + run);
  EXPECT_EQ(devices.exit_code, 1) << "stderr: " << devices.err;
  EXPECT_NE(devices.err.find("devices found: none; set in the environment: "
                             "POCL_DEVICES=no-such-kind"),
            std::string::npos)
      << devices.err;
}

// PoCL's pthread device crashes (SIGSEGV, exit 139) while OpenCL starts where
// POCL_MAX_PTHREAD_COUNT is negative, in `rvor devices` as in a run: refused before it starts.
TEST_F(CliErrors, ANegativePoclThreadCountIsRefusedBeforePoclStarts) {
  for (const std::string& command :
       {rvor_binary() + " devices",
        voronoi("--domain rect:-1,-1,1,1 --resolution 16 --random-seeds 3 --device pocl")}) {
    const CommandResult result = run_command("POCL_MAX_PTHREAD_COUNT=-1 " + command);
    EXPECT_EQ(result.exit_code, 1) << command << ": " << result.err;
    EXPECT_NE(result.err.find("rvor: error: POCL_MAX_PTHREAD_COUNT=-1 is negative (PoCL would "
                              "crash)"),
              std::string::npos)
        << result.err;
  }
  const CommandResult cpu =
      run_command("POCL_MAX_PTHREAD_COUNT=-1 " +
                  voronoi("--domain rect:-1,-1,1,1 --resolution 16 --random-seeds 3 --device cpu"));
  EXPECT_EQ(cpu.exit_code, 0) << "the reference does not start OpenCL: " << cpu.err;
}

bool has_pocl_device() {
  const std::vector<OpenCLDeviceInfo> devices = list_opencl_devices();
  return std::any_of(devices.begin(), devices.end(), [](const OpenCLDeviceInfo& device) {
    return device.platform == "Portable Computing Language";
  });
}

// A damaged PoCL kernel cache: an empty program.bc reads back as a program without kernels (the
// error was CL_INVALID_KERNEL_NAME alone), a garbled one fails PoCL's assertion, and garbled kernel
// .so files its dlopen, both of which aborted rvor (exit 134, its staging directory left). Now each
// ends with one rvor error line naming the cache to remove, exit code 1, and no output folders.
TEST_F(CliErrors, ADamagedPoclKernelCacheIsNamedAndAbortsBecomeErrors) {
  if (!has_pocl_device()) GTEST_SKIP() << "no PoCL device";
  const std::string cache = dir.file("pocl-cache");
  const std::string run = "POCL_CACHE_DIR=" + cache + " " + rvor_binary() +
                          " voronoi --quiet --device pocl --domain rect:-1,-1,1,1 --resolution 16 "
                          "--random-seeds 3 --out ";
  ASSERT_EQ(run_command(run + dir.file("warm")).exit_code, 0) << "filling the cache";
  struct Case {
    const char* damage;  // to each matching file of the cache
    const char* files;
    const char* expected;
  };
  for (const Case c :
       {Case{"truncate -s 0", "program.bc", "the compiled program lacks rvor's kernels"},
        Case{"sh -c 'head -c 2000 /dev/urandom >\"$0\"'", "program.bc", "the run aborted"},
        Case{"sh -c 'head -c 100 /dev/urandom >\"$0\"'", "*.so", "the run aborted"}}) {
    const std::string copy = dir.file("damaged");
    ASSERT_EQ(run_command("rm -rf " + copy + " && cp -a " + cache + " " + copy + " && find " +
                          copy + " -name '" + c.files + "' -exec " + c.damage + " {} \\;")
                  .exit_code,
              0);
    const std::string made = dir.file("made");
    const CommandResult result = run_command("POCL_CACHE_DIR=" + copy + " " + rvor_binary() +
                                             " voronoi --quiet --device pocl --domain "
                                             "rect:-1,-1,1,1 --resolution 16 --random-seeds 3 "
                                             "--out " +
                                             made + "/out");
    EXPECT_EQ(result.exit_code, 1) << c.files << ": " << result.err;
    const std::size_t last = result.err.rfind('\n', result.err.size() - 2);
    const std::string last_line = result.err.substr(last == std::string::npos ? 0 : last + 1);
    EXPECT_EQ(last_line.rfind("rvor: error: ", 0), 0u) << result.err;
    EXPECT_NE(last_line.find(c.expected), std::string::npos) << result.err;
    EXPECT_NE(last_line.find("remove PoCL's, " + copy + ", and run again"), std::string::npos)
        << result.err;
    EXPECT_FALSE(std::filesystem::exists(made)) << c.files << ": " << result.err;
  }
}

// LLVM ends the process with exit(1) where PoCL's compiler cannot write its kernel cache past a
// point (a full disk: "LLVM ERROR: IO failure on output stream"; here a file size limit): the run
// left its staging directory and created folders, its progress line open, and no rvor error line.
TEST_F(CliErrors, AnExitInsidePoclsCompilerCleansUpAndNamesTheCache) {
  if (!has_pocl_device()) GTEST_SKIP() << "no PoCL device";
  const std::string cache = dir.file("fresh-pocl-cache");
  const std::string made = dir.file("made");
  const CommandResult result =
      run_command("(ulimit -f 400; POCL_CACHE_DIR=" + cache + " " + rvor_binary() +
                  " voronoi --device pocl --domain rect:-1,-1,1,1 --resolution 16 "
                  "--random-seeds 3 --out " +
                  made + "/out)");
  if (result.err.find("LLVM ERROR") == std::string::npos)
    GTEST_SKIP() << "the limit did not reach LLVM's output here: " << result.err;
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("\n failed\nrvor: error: a library it calls ended the run"),
            std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find("kernel cache, " + cache + " (a full disk"), std::string::npos)
      << result.err;
  EXPECT_FALSE(std::filesystem::exists(made)) << result.err;
}

// A canvas too big for the device is refused before the solve with the sizes, not a failure at a
// later command. POCL_MEMORY_LIMIT=1 gives PoCL's device 1 GiB, buffers up to 256 MiB; the stencil
// records of radial_shock_3d at 224^3 (28 B for each of 11.2M slots) need 300.1 MiB.
TEST_F(CliErrors, CanvasTooBigForTheDeviceNamesTheSizes) {
  if (!has_pocl_device()) GTEST_SKIP() << "no PoCL device";
  const CommandResult result = run_command(
      "POCL_MEMORY_LIMIT=1 " + voronoi("--device pocl --domain box:1,1,1,11,11,11 --metric "
                                       "radial_shock_3d --resolution 224 --random-seeds 10"));
  EXPECT_EQ(result.exit_code, 1) << "stderr: " << result.err;
  EXPECT_NE(result.err.find("the canvas needs a device buffer of 301 MiB, over the largest one "
                            "OpenCL device '"),
            std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find("allocates (256 MiB)"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("or --device cpu (the CPU reference solver"), std::string::npos)
      << result.err;
  EXPECT_FALSE(std::filesystem::exists(out() + "/voronoi.vdb"));
}

// A kernel build that fails without a compiler message (PoCL unable to write its cache, here by a
// file size limit on a fresh cache) is one line, says where to look, and keeps the build log; it
// was four lines, one of them blank, naming no cause.
TEST_F(CliErrors, AKernelBuildFailureIsOneLineAndNamesTheCache) {
  if (!has_pocl_device()) GTEST_SKIP() << "no PoCL device";
  const CommandResult result = run_command(
      "(ulimit -f 8; POCL_CACHE_DIR=" + dir.file("fresh-pocl-cache") + " " +
      voronoi("--device pocl --domain rect:-1,-1,1,1 --resolution 16 --random-seeds 3") + ")");
  EXPECT_EQ(result.exit_code, 1) << "stderr: " << result.err;
  EXPECT_EQ(result.err.find('\n'), result.err.size() - 1) << "more than one line: " << result.err;
  EXPECT_NE(result.err.find("OpenCL program build failed"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("the build log holds no compiler message"), std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find("build log: | Device "), std::string::npos) << result.err;
}

}  // namespace
}  // namespace rvor::test
