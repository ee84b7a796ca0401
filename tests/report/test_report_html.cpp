// `floorcast report` rendered by headless Chromium (Debian's chromium): a small scenario is run,
// report.html written, screenshotted and its DOM dumped after rendering. Checks: the page is not
// blank (the styled header band is drawn, the embedded plots bring many colours), the summary
// tables are present with header and data rows, every image is embedded (one self-contained file).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <set>
#include <string>

#include "floorcast/core/file_io.hpp"
#include "floorcast/core/image_io.hpp"

namespace fs = std::filesystem;

namespace {

std::string quote(const std::string& s) { return "'" + s + "'"; }

int run(const std::string& command) { return std::system(command.c_str()); }

std::string browser() {
  for (const char* b : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (fs::exists(b)) return b;
  return "";
}

class ReportHtml : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // A folder per test process: ctest runs each test of this suite as its own process, in
    // parallel, and each sets the run up.
    work_ = fs::path(FLOORCAST_TEST_WORK_DIR) / std::to_string(::getpid());
    fs::remove_all(work_);
    fs::create_directories(work_);
    const std::string cli = FLOORCAST_CLI_PATH;
    ASSERT_EQ(run(quote(cli) + " run " + quote(FLOORCAST_REPORT_SCENARIO) + " -o " + quote((work_ / "run").string()) +
                  " --quiet --jobs 2 > /dev/null"),
              0);
    ASSERT_EQ(run(quote(cli) + " report " + quote((work_ / "run").string()) + " -o " + quote((work_ / "report.html").string())), 0);
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(work_, ec);
  }
  static fs::path work_;
};
fs::path ReportHtml::work_;

TEST_F(ReportHtml, SelfContained) {
  const std::string html = floorcast::read_text_file((work_ / "report.html").string());
  EXPECT_NE(html.find("<table>"), std::string::npos);
  EXPECT_FALSE(std::regex_search(html, std::regex("src=\"(?!data:)"))) << "an image is not embedded";
  EXPECT_FALSE(std::regex_search(html, std::regex("<link[^>]+href="))) << "an external stylesheet";
  EXPECT_NE(html.find("Resolved configuration"), std::string::npos);
  EXPECT_NE(html.find("Best and worst heatmaps"), std::string::npos);
}

TEST_F(ReportHtml, ReadableHeaderTrueBestWorstAndFullSizeOnClick) {
  const std::string html = floorcast::read_text_file((work_ / "report.html").string());
  // The description once (header), not again above the tables (the resolved configuration at the
  // end lists it as a value); a short configuration id.
  const std::string desc = "Report test (two axes, one of them zipped).";
  const std::string page = html.substr(0, html.find("<section id=\"config\">"));
  std::size_t count = 0;
  for (std::size_t p = page.find(desc); p != std::string::npos; p = page.find(desc, p + 1)) ++count;
  EXPECT_EQ(count, 1u);
  EXPECT_NE(html.find("32 observations in 2 buildings (two_rooms, apartment)"), std::string::npos);
  // Best and worst over all 32 units per method (6 + 6 each), not only over the 16 heatmaps the
  // run kept: the others are drawn for the page.
  EXPECT_NE(html.find("Heatmaps the run did not keep were drawn for this page."), std::string::npos);
  EXPECT_EQ(html.find("(no heatmap)"), std::string::npos);
  const std::regex heat("<figure class=\"heat\"><img");
  const auto n = std::distance(std::sregex_iterator(html.begin(), html.end(), heat), std::sregex_iterator());
  EXPECT_EQ(n, 2 * 12);
  for (const char* t : {"<h3>Best 6, kernel</h3>", "<h3>Worst 6, kernel</h3>", "<h3>Best 6, ray</h3>", "<h3>Worst 6, ray</h3>"})
    EXPECT_NE(html.find(t), std::string::npos) << t;
  // Every picture opens full size on a click (one overlay, no second copy of the data).
  EXPECT_NE(html.find("onclick=\"fullSize(this)\""), std::string::npos);
  EXPECT_NE(html.find("id=\"overlay\""), std::string::npos);
}

TEST_F(ReportHtml, RenderedByChromium) {
  const std::string b = browser();
  ASSERT_FALSE(b.empty()) << "chromium is not installed (bash scripts/install_deps.sh --test installs Debian's chromium)";
  const std::string flags = " --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run --disable-dev-shm-usage"
                            " --user-data-dir=" + quote((work_ / "profile").string());
  const std::string url = "file://" + fs::absolute(work_ / "report.html").string();
  const fs::path shot = work_ / "screenshot.png", dom_file = work_ / "dom.html";
  ASSERT_EQ(run("timeout 120 " + quote(b) + flags + " --window-size=1280,3600 --screenshot=" + quote(shot.string()) + " " +
                quote(url) + " > /dev/null 2>&1"),
            0);
  ASSERT_EQ(run("timeout 120 " + quote(b) + flags + " --dump-dom " + quote(url) + " > " + quote(dom_file.string()) + " 2>/dev/null"), 0);

  // Tables are present in the rendered page, with header and data rows.
  const std::string dom = floorcast::read_text_file(dom_file.string());
  const std::regex table_re("<table>([\\s\\S]*?)</table>");
  int tables = 0;
  for (auto it = std::sregex_iterator(dom.begin(), dom.end(), table_re); it != std::sregex_iterator(); ++it) {
    ++tables;
    const std::string t = (*it)[1];
    EXPECT_NE(t.find("<th>"), std::string::npos);
    EXPECT_NE(t.find("<td>"), std::string::npos);
  }
  EXPECT_GE(tables, 4);  // one per cell (4 cells) plus the sweep overview
  EXPECT_NE(dom.find("@1"), std::string::npos) << "recall columns missing";
  std::size_t images = 0;
  for (std::size_t p = dom.find("<img"); p != std::string::npos; p = dom.find("<img", p + 1)) ++images;
  EXPECT_GE(images, 6u) << "plots and heatmaps missing from the rendered page";

  // The screenshot is not blank: the styled header band is drawn; plots bring many colours.
  const cv::Mat img = floorcast::read_image(shot.string());
  ASSERT_GE(img.cols, 1000);
  ASSERT_GE(img.rows, 1000);
  const int ch = img.channels();
  ASSERT_GE(ch, 3);
  long navy = 0, header = 0, non_white = 0;
  std::set<int> colours;
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) {
      const std::uint8_t* p = img.ptr<std::uint8_t>(r) + c * ch;  // BGR(A)
      const int bb = p[0], gg = p[1], rr = p[2];
      if (r >= 5 && r < 40 && c >= 10 && c < 400) {
        ++header;
        navy += std::abs(rr - 0x1f) + std::abs(gg - 0x3b) + std::abs(bb - 0x57) < 30;
      }
      non_white += rr + gg + bb < 740;
      colours.insert((bb >> 3) << 10 | (gg >> 3) << 5 | (rr >> 3));
    }
  const double non_white_share = static_cast<double>(non_white) / static_cast<double>(img.total());
  std::printf("screenshot %dx%d: %.1f%% non-white, %zu colours, %d tables, %zu images\n", img.cols, img.rows,
              100.0 * non_white_share, colours.size(), tables, images);
  EXPECT_GT(static_cast<double>(navy) / static_cast<double>(header), 0.5) << "the styled header is not rendered";
  EXPECT_GT(non_white_share, 0.05) << "the page is nearly blank";
  EXPECT_GT(colours.size(), 200u) << "too few colours: plots not rendered";
}

}  // namespace
