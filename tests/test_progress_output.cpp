// Progress on stderr (issue 21): `xsect run` on a pseudo-terminal draws bars with counts for the
// long stages (segment over frames, conform over pairs, reconstruct and smooth over blocks) and
// ends with the verdict, the Betti numbers and the path of report.html; with stderr in a file it
// writes exactly one line per stage and no bar; `--quiet` writes nothing. The Progress class
// itself: one line per stage off a terminal, bars redrawn at most ten times a second and only
// when they change, the time left once it means something, updates from many threads at once,
// nothing when quiet or unwinding.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "cli.h"
#include "pipeline/progress.h"

namespace fs = std::filesystem;
using xsect::Progress;
using xsect::test::CliResult;
using xsect::test::runXsect;

namespace {

/// Runs `xsect ARGS` with stderr on a pseudo-terminal (stdin and stdout on /dev/null) and returns
/// its exit code and every byte the terminal received. The terminal is raw (no "\n" -> "\r\n"),
/// so the bytes are those xsect wrote. Killed after timeout_s seconds without output.
CliResult runOnTerminal(const std::vector<std::string>& args, int timeout_s = 120) {
  CliResult r;
  int master = -1, slave = -1;
  termios raw{};
  cfmakeraw(&raw);
  winsize size{};
  size.ws_row = 40;
  size.ws_col = 160;
  if (::openpty(&master, &slave, nullptr, &raw, &size) != 0) {
    r.err = "openpty failed";
    return r;
  }
  std::vector<std::string> words{XSECT_BIN};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {  // only async-signal-safe calls until exec
    ::close(master);
    const int null = ::open("/dev/null", O_RDWR);
    ::dup2(null, 0);
    ::dup2(null, 1);
    ::dup2(slave, 2);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  ::close(slave);  // else the master never sees the terminal closed
  char buf[4096];
  for (;;) {
    pollfd p{master, POLLIN, 0};
    const int ready = ::poll(&p, 1, timeout_s * 1000);
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) {
      ::kill(pid, SIGKILL);
      break;
    }
    const ssize_t n = ::read(master, buf, sizeof buf);
    if (n > 0) {
      r.err.append(buf, std::size_t(n));
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      break;  // EIO: every copy of the slave is closed, the child has exited
    }
  }
  ::close(master);
  int status = 0;
  ::waitpid(pid, &status, 0);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// A fresh folder with the torus-multiaxial phantom (30 slices) rendered into ph/.
fs::path torusPhantom(const std::string& tag) {
  const fs::path dir = xsect::test::freshDir(tag);
  const auto r = runXsect("phantom " + std::string(XSECT_SOURCE_DIR) +
                          "/configs/phantoms/torus-multiaxial.yaml --out " + (dir / "ph").string() + " --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  return dir;
}

std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// The last four lines of `xsect run`: the sampling verdict, the Betti numbers of report.json with
/// its topology confidence, what they mean in plain words (report.json in_plain_words), the path of
/// report.html in `out`; plain lines (no bar left on them).
void expectClosingLines(const std::string& err, const fs::path& out) {
  const std::vector<std::string> lines = linesOf(err);
  ASSERT_GE(lines.size(), 4u) << err;
  const std::string& verdict = lines[lines.size() - 4];
  const std::string& betti = lines[lines.size() - 3];
  const std::string& meaning = lines[lines.size() - 2];
  const std::string& report = lines[lines.size() - 1];
  const nlohmann::json rep = nlohmann::json::parse(xsect::test::slurp(out / "report.json"));
  const std::string name = rep["sampling"]["verdict"].get<std::string>();
  EXPECT_EQ(verdict.rfind("sampling: " + name, 0), 0u) << err;
  const std::string topology = "topology: " + std::to_string(rep["betti"][0].get<int>()) + " " +
                               std::to_string(rep["betti"][1].get<int>()) + " " + std::to_string(rep["betti"][2].get<int>()) +
                               ", confidence " + rep["topology"]["confidence"]["text"].get<std::string>();
  EXPECT_EQ(betti.rfind(topology, 0), 0u) << err;
  EXPECT_EQ(meaning, rep["in_plain_words"].get<std::string>()) << err;
  EXPECT_EQ(report, "report: " + (fs::absolute(out) / "report.html").string()) << err;
  for (const std::string* l : {&verdict, &betti, &meaning, &report})
    EXPECT_EQ(l->find_first_of("\r\033"), std::string::npos) << *l;
}

/// Everything written to `f` (a tmpfile).
std::string contents(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) s.append(buf, n);
  std::fclose(f);
  return s;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(ProgressOutput, TerminalShowsBarsWithCountsAndClosingLines) {
  const fs::path dir = torusPhantom("progress-tty");
  const fs::path out = dir / "r";
  const CliResult r = runOnTerminal({"run", (dir / "ph/config.yaml").string(), "--out", out.string(), "--set",
                                     "smoothing.method=shepard"});
  ASSERT_EQ(r.code, 0) << r.err;
  // Each long stage drew its bar at least once, with its counts, and ended with its count.
  for (const auto& [stage, unit] : std::map<std::string, std::string>{
           {"segment", "frames"}, {"conform", "pairs"}, {"reconstruct", "blocks"}, {"smooth", "blocks"}}) {
    SCOPED_TRACE(stage);
    std::smatch bar, end;
    const std::regex barRe("\r\\[" + stage + "\\] \\[[#-]{20}\\] +([0-9]+)/([0-9]+) " + unit + "[^\r\n]*\033\\[K");
    ASSERT_TRUE(std::regex_search(r.err, bar, barRe)) << r.err;
    EXPECT_LE(std::stoll(bar[1].str()), std::stoll(bar[2].str()));
    const std::regex endRe("\r\\[" + stage + "\\] ([0-9]+) " + unit + " in [0-9.]+ s\033\\[K\n");
    ASSERT_TRUE(std::regex_search(r.err, end, endRe)) << r.err;
    EXPECT_EQ(end[1].str(), bar[2].str()) << "the final count is the bar's total";
  }
  EXPECT_NE(r.err.find("\r[segment] 30 frames in"), std::string::npos) << r.err;
  expectClosingLines(r.err, out);
  fs::remove_all(dir);
}

TEST(ProgressOutput, OffATerminalOneLinePerStage) {
  const fs::path dir = torusPhantom("progress-file");
  const fs::path out = dir / "r";
  const CliResult r = runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find_first_of("\r\033"), std::string::npos) << "no bar, no terminal control:\n" << r.err;
  std::map<std::string, int> lines;  // "[stage] ..." lines by stage
  const std::regex stageLine("\\[([a-z ]+)\\] (done|[0-9]+ [a-z]+) in [0-9.]+ s");
  for (const std::string& line : linesOf(r.err)) {
    if (line.empty() || line[0] != '[') continue;
    std::smatch m;
    ASSERT_TRUE(std::regex_match(line, m, stageLine)) << line;
    ++lines[m[1].str()];
  }
  for (const auto& [stage, n] : lines) EXPECT_EQ(n, 1) << stage;
  for (const char* stage : {"load", "segment", "conform", "scene", "arrange", "reconstruct", "mesh", "diagnose",
                            "sampling", "write"})
    EXPECT_EQ(lines.count(stage), 1u) << stage << "\n" << r.err;
  EXPECT_NE(r.err.find("[segment] 30 frames in "), std::string::npos) << r.err;
  EXPECT_TRUE(std::regex_search(r.err, std::regex("\\[conform\\] 435 pairs in ")))  // 30 * 29 / 2
      << r.err;
  EXPECT_TRUE(std::regex_search(r.err, std::regex("\\[reconstruct\\] [0-9]+ blocks in "))) << r.err;
  expectClosingLines(r.err, out);
  fs::remove_all(dir);
}

TEST(ProgressOutput, QuietPrintsNothingOnSuccess) {
  const fs::path dir = torusPhantom("progress-quiet");
  const CliResult inFile = runXsect("run " + (dir / "ph/config.yaml").string() + " --out " + (dir / "a").string() +
                                    " --quiet");
  EXPECT_EQ(inFile.code, 0) << inFile.err;
  EXPECT_EQ(inFile.err, "");
  const CliResult onTerminal =
      runOnTerminal({"run", (dir / "ph/config.yaml").string(), "--out", (dir / "b").string(), "--quiet"});
  EXPECT_EQ(onTerminal.code, 0) << onTerminal.err;
  EXPECT_EQ(onTerminal.err, "");
  EXPECT_TRUE(fs::exists(dir / "b/report.json"));
  fs::remove_all(dir);
}

TEST(ProgressOutputClass, OffATerminalOnlyTheStagesLines) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    Progress p(false, false, f);
    p.stage("segment", "frames");
    for (int i = 1; i <= 400; ++i) p.update(i, 400);
    p.stage("scene");
    p.update(0.5);
    p.note("a note");
    p.stage("mesh");
  }
  const std::string s = contents(f);
  EXPECT_TRUE(std::regex_match(s, std::regex("\\[segment\\] 400 frames in [0-9.]+ s\n"
                                              "\\[scene\\] done in [0-9.]+ s\n"
                                              "a note\n"
                                              "\\[mesh\\] done in [0-9.]+ s\n")))
      << s;
}

TEST(ProgressOutputClass, TerminalBarIsThrottledAndEndsWithItsLine) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  {
    Progress p(false, true, f);
    p.stage("segment", "frames");
    for (int i = 1; i <= 40; ++i) {  // 40 updates over 0.4 s
      p.update(i, 40);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    p.finish();
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string s = contents(f);
  const std::regex whole("(\r\\[segment\\] \\[[#-]{20}\\]  +[0-9]+/40 frames(  [0-9]+:[0-9]{2} left)?\033\\[K)+"
                         "\r\\[segment\\] 40 frames in [0-9.]+ s\033\\[K\n");
  EXPECT_TRUE(std::regex_match(s, whole)) << s;
  const std::size_t bars = count(s, "\r[segment] [");
  EXPECT_GE(bars, 2u) << s;
  EXPECT_LE(double(bars), 2 + elapsed / 0.1) << "at most ten redraws a second:\n" << s;
  EXPECT_NE(s.find("\r[segment] [--------------------]   1/40 frames"), std::string::npos)
      << "the first update draws at once:\n" << s;
}

TEST(ProgressOutputClass, UnchangedBarIsNotRedrawnAndFractionsShowPercent) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    Progress p(false, true, f);
    p.stage("reconstruct");
    p.update(0.42);
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    p.update(0.42);  // the same text: not written again
  }
  const std::string s = contents(f);
  EXPECT_EQ(count(s, "\r[reconstruct] ["), 1u) << s;
  EXPECT_NE(s.find("\r[reconstruct] [########------------]   42%"), std::string::npos) << s;
  EXPECT_TRUE(std::regex_search(s, std::regex("\r\\[reconstruct\\] done in [0-9.]+ s\033\\[K\n$"))) << s;
}

TEST(ProgressOutputClass, TimeLeftOnceTheStageHasRunHalfASecond) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    Progress p(false, true, f);
    p.stage("smooth", "blocks");
    p.update(1, 4);
    std::this_thread::sleep_for(std::chrono::milliseconds(600));
    p.update(2, 4);  // 0.6 s for half the blocks: as long again
  }
  const std::string s = contents(f);
  EXPECT_NE(s.find("\r[smooth] [#####---------------]  1/4 blocks\033[K"), std::string::npos) << s;
  // 0:01 when the sleep took 0.6 s; a loaded machine may sleep longer (0:02).
  EXPECT_TRUE(std::regex_search(s, std::regex("\r\\[smooth\\] \\[##########----------\\]  2/4 blocks  0:0[12] left\033\\[K")))
      << s;
}

TEST(ProgressOutputClass, UpdatesFromManyThreads) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    Progress p(false, true, f);
    p.stage("conform", "pairs");
    const std::function<void(std::int64_t, std::int64_t)> report = p.counter();
    std::atomic<std::int64_t> done{0};
    tbb::parallel_for(0, 400000, [&](int) { report(++done, 400000); });
  }
  const std::string s = contents(f);
  // Whole bars only (no two threads writing at once), then the stage's line.
  EXPECT_TRUE(std::regex_match(s, std::regex("(\r\\[conform\\] \\[[#-]{20}\\]  +[0-9]+/400000 pairs"
                                             "(  [0-9]+:[0-9]{2} left)?\033\\[K)+"
                                             "\r\\[conform\\] 400000 pairs in [0-9.]+ s\033\\[K\n")))
      << s;
}

TEST(ProgressOutputClass, QuietWritesNothing) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    Progress p(true, true, f);
    p.stage("segment", "frames");
    p.update(3, 4);
    p.update(0.5);
    p.note("warning: something");
    p.stage("write");
  }
  EXPECT_EQ(contents(f), "");
}

TEST(ProgressOutputClass, NoStageLineWhileAnExceptionUnwinds) {
  std::FILE* file = std::tmpfile();
  std::FILE* terminal = std::tmpfile();
  ASSERT_NE(file, nullptr);
  ASSERT_NE(terminal, nullptr);
  try {
    Progress p(false, false, file);
    Progress q(false, true, terminal);
    p.stage("segment", "frames");
    q.stage("segment", "frames");
    p.update(1, 4);
    q.update(1, 4);
    throw std::runtime_error("bad frame");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(contents(file), "");
  const std::string s = contents(terminal);
  EXPECT_EQ(s.find(" in "), std::string::npos) << s;
  ASSERT_FALSE(s.empty());
  EXPECT_EQ(s.back(), '\n') << "the error starts a line of its own";
}
