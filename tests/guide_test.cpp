// The assembly guide and the pictures, checked from outside: the files a run writes, the data
// file parsed by an independent JSON reader, the pictures read back as PNG, and the page opened
// from the file system in headless Chromium (Debian's chromium; skipped where it is absent):
// no error on the page, one mesh per part, stepping to step k highlights the k-th part of the
// order, and a screenshot whose 3D view is not blank.
#include <cairo.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

#include "kerfab/output/render3d.h"
#include "kerfab/output/run_output.h"
#include "kerfab/pipeline/pipeline.h"
#include "fixtures.h"
#include "test_util.h"

namespace kerfab {
namespace {
namespace fs = std::filesystem;

/// A closed cylinder run end to end and written to a fresh directory of the running test's own
/// (ctest runs the tests that share it as parallel processes).
struct Written {
  RunResult run;
  fs::path dir;
};

const Written& written() {
  static const Written w = [] {
    const test::Shape shape = test::closed_cylinder(40, 80, 3);
    const fs::path dir = test::fresh_dir(".guide_run");
    PipelineOptions o;
    o.layout.sheet_width = 300;
    o.layout.sheet_height = 200;
    Written out{test::run_shape(shape, o, dir), dir / "out"};
    fs::create_directories(out.dir);
    write_run(out.run, {}, out.dir);
    return out;
  }();
  return w;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;

/// Pixels of a PNG that are not near-white, and distinct colours among them (coarsely binned).
std::pair<long, int> ink(const fs::path& png, int x0 = 0, int x1 = 1 << 30) {
  Surface s(cairo_image_surface_create_from_png(png.c_str()), cairo_surface_destroy);
  if (cairo_surface_status(s.get()) != CAIRO_STATUS_SUCCESS) return {-1, 0};
  const int w = cairo_image_surface_get_width(s.get()), h = cairo_image_surface_get_height(s.get());
  const int stride = cairo_image_surface_get_stride(s.get());
  const unsigned char* data = cairo_image_surface_get_data(s.get());
  long count = 0;
  std::set<int> colours;
  for (int y = 0; y < h; ++y)
    for (int x = std::max(0, x0); x < std::min(w, x1); ++x) {
      const unsigned char* p = data + y * stride + 4 * x;  // B G R A
      if (p[0] > 235 && p[1] > 235 && p[2] > 235) continue;
      ++count;
      colours.insert((p[0] / 32) * 64 + (p[1] / 32) * 8 + p[2] / 32);
    }
  return {count, static_cast<int>(colours.size())};
}

using CairoSurfaceForTest = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;

/// The colour of pixel (x, y) of an RGB24 image surface.
std::array<int, 3> pixel(cairo_surface_t* image, double x, double y) {
  cairo_surface_flush(image);
  const unsigned char* data = cairo_image_surface_get_data(image);
  const int stride = cairo_image_surface_get_stride(image);
  const auto v = *reinterpret_cast<const std::uint32_t*>(
      data + static_cast<int>(y) * stride + 4 * static_cast<int>(x));
  return {static_cast<int>(v >> 16 & 255), static_cast<int>(v >> 8 & 255),
          static_cast<int>(v & 255)};
}

TEST(Guide, StepPicturesShowTheNearestPlacedFaceWhateverTheOrderOfPlacing) {
  // Two squares facing the viewer, seen straight on (z up, looking along +y): A (tag 0) at
  // depth 1 over x, z in [0, 2] with a stroke along its top side, B (tag 1) nearer, at depth 0
  // over [1, 3]. B is placed first, then A: where they overlap B must stay in front, and A's
  // stroke must show only where B does not cover it.
  Face3 a, b;
  a.corners = {{0, 1, 0}, {2, 1, 0}, {2, 1, 2}, {0, 1, 2}};
  a.tag = 0;
  a.sides.push_back({2, {0, 0, 0}, 4.0, 1.0});  // corner 2 -> 3: the top, z = 2
  b.corners = {{1, 0, 1}, {3, 0, 1}, {3, 0, 3}, {1, 0, 3}};
  b.tag = 1;
  const std::vector<Face3> faces{a, b};
  ViewOptions straight;
  straight.up = 2;
  straight.azimuth = 0;
  straight.elevation = 0;
  const View3 view(corners_of(faces), straight, 0, 0, 300, 300);
  const FacePainter painter(view, faces);
  LayeredPicture picture(painter, 300, 300);
  CairoSurfaceForTest image(cairo_image_surface_create(CAIRO_FORMAT_RGB24, 300, 300),
                            cairo_surface_destroy);
  const auto colour = [](int tag) { return tag == 0 ? Rgb{1, 0, 0} : Rgb{0, 0, 1}; };
  const auto at = [&](double x, double z) {
    const auto s = view.screen({x, 0.5, z});
    return pixel(image.get(), s[0], s[1]);
  };
  const std::array<int, 3> white{255, 255, 255};
  picture.paint(image.get(), colour);
  EXPECT_EQ(at(0.5, 0.5), white);  // nothing placed yet
  picture.add(1);
  picture.paint(image.get(), colour);
  EXPECT_EQ(at(0.5, 0.5), white);
  EXPECT_GT(at(1.5, 1.5)[2], 100);  // B
  EXPECT_EQ(at(1.5, 1.5)[0], 0);
  picture.add(0);
  picture.paint(image.get(), colour);
  EXPECT_GT(at(0.5, 0.5)[0], 100);  // A where B is not
  EXPECT_EQ(at(0.5, 0.5)[2], 0);
  EXPECT_GT(at(1.5, 1.5)[2], 100);  // B in front of A, though placed first
  EXPECT_EQ(at(1.5, 1.5)[0], 0);
  EXPECT_EQ(at(0.5, 2.0), (std::array<int, 3>{0, 0, 0}));  // A's stroke in the open
  EXPECT_GT(at(1.5, 2.0)[2], 100);                         // and hidden behind B
  EXPECT_EQ(at(2.5, 0.5), white);
}

TEST(Guide, EveryRunWritesTheGuideAndPictures) {
  const Written& w = written();
  const auto& plan = *w.run.assembly;
  const int parts = static_cast<int>(w.run.joints->parts.size());
  for (const char* f : {"index.html", "guide.js", "model.js", "three.min.js", "OrbitControls.js",
                        "steps.pdf"})
    EXPECT_TRUE(fs::is_regular_file(w.dir / "assembly" / f)) << f;
  // three.js as Debian ships it, byte for byte.
  EXPECT_EQ(read_text(w.dir / "assembly" / "three.min.js"),
            read_text("/usr/share/javascript/three/three.min.js"));
  // The page loads only files beside it: no http(s) address anywhere in it.
  const std::string html = read_text(w.dir / "assembly" / "index.html");
  EXPECT_EQ(html.find("http"), std::string::npos);
  for (const char* src : {"three.min.js", "OrbitControls.js", "model.js", "guide.js"})
    EXPECT_NE(html.find(std::string("src=\"") + src + "\""), std::string::npos) << src;
  // model.js: one entry per part with a mesh, the steps in the report's order.
  const std::string js = read_text(w.dir / "assembly" / "model.js");
  const auto start = js.find('{');
  ASSERT_NE(start, std::string::npos);
  const auto model = nlohmann::json::parse(js.substr(start, js.rfind('}') - start + 1));
  ASSERT_EQ(static_cast<int>(model["parts"].size()), parts);
  for (int p = 0; p < parts; ++p) {
    const auto& part = model["parts"][p];
    EXPECT_EQ(part["n"], p);
    EXPECT_GT(part["tri"].size(), 0u);
    EXPECT_EQ(part["pos"].size() % 3, 0u);
    for (const auto& i : part["tri"]) EXPECT_LT(3 * i.get<std::size_t>(), part["pos"].size());
  }
  const auto report = nlohmann::json::parse(std::ifstream(w.dir / "report.json"));
  ASSERT_EQ(report["assembly"]["order"].size(), plan.steps.size());
  for (std::size_t k = 0; k < plan.steps.size(); ++k) {
    EXPECT_EQ(model["steps"][k]["part"], plan.steps[k].part);
    EXPECT_EQ(report["assembly"]["order"][k], plan.steps[k].part);
  }
  // steps.pdf: a PDF with one page per 20 steps.
  const std::string pdf = read_text(w.dir / "assembly" / "steps.pdf");
  EXPECT_EQ(pdf.rfind("%PDF-", 0), 0u);
  const std::regex page_re(R"(/Type\s*/Page[^s])");
  const auto pages = std::distance(std::sregex_iterator(pdf.begin(), pdf.end(), page_re),
                                   std::sregex_iterator());
  EXPECT_EQ(pages, (static_cast<long>(plan.steps.size()) + 19) / 20);
  // Pictures: each a PNG with a drawing on it (not blank, several colours).
  for (const char* f : {"bending.png", "strips.png", "kerf_density.png", "patches.png",
                        "parts.png"}) {
    const auto [count, colours] = ink(w.dir / "pictures" / f);
    EXPECT_GT(count, 5000) << f;
    EXPECT_GE(colours, 3) << f;
  }
}

/// Runs headless Chromium on the page at \p hash; returns the DOM after the scripts ran, and
/// writes a screenshot to \p png when given.
std::string open_page(const fs::path& dir, const std::string& hash, const fs::path& png = {}) {
  const std::string url = "file://" + (dir / "assembly" / "index.html").string() + "#" + hash;
  const std::string flags =
      "--headless=new --no-sandbox --disable-gpu --enable-unsafe-swiftshader "
      "--use-angle=swiftshader --window-size=1200,800 --virtual-time-budget=10000 "
      "--no-first-run --disable-extensions --user-data-dir=" +
      (dir / "chromium-profile").string();
  const std::string cmd = "/usr/bin/chromium " + flags +
                          (png.empty() ? " --dump-dom '" : " --screenshot='" + png.string() + "' '") +
                          url + "' 2>" + (dir / "chromium.err").string();
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  if (!pipe) return out;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe.get())) > 0) out.append(buf.data(), n);
  return out;
}

std::string body_attribute(const std::string& dom, const std::string& name) {
  const std::regex re("<body[^>]*\\sdata-" + name + "=\"([^\"]*)\"");
  std::smatch m;
  return std::regex_search(dom, m, re) ? m[1].str() : std::string("(absent)");
}

TEST(Guide, OpensInHeadlessChromium) {
  if (!fs::exists("/usr/bin/chromium"))
    GTEST_SKIP() << "Debian's chromium is not installed (scripts/test.sh installs it)";
  const Written& w = written();
  const auto& plan = *w.run.assembly;
  const int n = static_cast<int>(plan.steps.size());
  for (const int k : {0, 1, n / 2, n}) {
    SCOPED_TRACE("step " + std::to_string(k));
    const std::string dom = open_page(w.dir, "step=" + std::to_string(k));
    ASSERT_EQ(body_attribute(dom, "ready"), "1") << dom.substr(0, 500);
    EXPECT_EQ(body_attribute(dom, "errors"), "(absent)");
    EXPECT_EQ(body_attribute(dom, "meshes"), std::to_string(w.run.joints->parts.size()));
    EXPECT_EQ(body_attribute(dom, "step"), std::to_string(k));
    EXPECT_EQ(body_attribute(dom, "highlighted"),
              k == 0 ? std::string() : std::to_string(plan.steps[k - 1].part));
    const std::string err = read_text(w.dir / "chromium.err");
    EXPECT_EQ(err.find("Uncaught"), std::string::npos) << err;
  }
  // A click target by number: the search box's path, through the hash.
  const int part = plan.steps[n - 1].part;
  const std::string dom = open_page(w.dir, "part=" + std::to_string(part));
  EXPECT_EQ(body_attribute(dom, "selected"), std::to_string(part));
  EXPECT_NE(dom.find("Part " + std::to_string(part) + "</span>"), std::string::npos);
  // The screenshot shows the model: the 3D view (right of the 360 px panel) holds many drawn
  // pixels in several colours.
  const fs::path png = w.dir / "guide.png";
  open_page(w.dir, "step=" + std::to_string(n / 2), png);
  const auto [count, colours] = ink(png, 370);
  EXPECT_GT(count, 20000);
  EXPECT_GE(colours, 4);
}

}  // namespace
}  // namespace kerfab
