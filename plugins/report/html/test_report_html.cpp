#include <gtest/gtest.h>

#include <lista/basic_context.hpp>
#include <lista/lista.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <tuple>
#include <sstream>

namespace fs = std::filesystem;

namespace lista_plugin_detail {
const lista::PluginManifest* manifest();
}

namespace {

// A room of 4 walls scanned from two origins, plus three changed objects:
// one removed (mission A), one added (B) and one moved (A -> B).
struct Scene {
  lista::MissionSet missions;
  lista::ObjectSet objects;
  lista::Groups groups;
  lista::Matches matches;
  lista::DescriptorSet descriptors;
};

lista::PointSet box_points(const Eigen::Vector3f& centre, float half, int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-half, half);
  lista::PointSet p;
  for (int i = 0; i < n; ++i) {
    p.xyz.push_back(centre + Eigen::Vector3f(u(rng), u(rng), u(rng)));
    p.scan.push_back(0);
    p.index.push_back(uint32_t(i));
  }
  return p;
}


// One object's entry; a move gets cost 0.1, confidence 0.95 and a transform.
lista::ObjectChange change(int id, lista::ChangeStatus status, int match = -1) {
  lista::ObjectChange c;
  c.object_id = id;
  c.status = status;
  c.match = match;
  if (status == lista::ChangeStatus::moved) {
    c.cost = 0.1;
    c.confidence = 0.95;
    c.has_transform = true;
  }
  return c;
}

Scene make_scene() {
  Scene s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-5, 5), h(0, 2.5);
  for (const char* name : {"A", "B"}) {
    lista::Mission m;
    m.name = name;
    lista::Scan scan;
    auto pts = std::make_shared<lista::PointSet>();
    for (int i = 0; i < 4000; ++i) {
      const float t = u(rng), z = h(rng);
      const Eigen::Vector3f wall[4] = {{t, -5, z}, {t, 5, z}, {-5, t, z}, {5, t, z}};
      pts->xyz.push_back(wall[i % 4]);
      pts->scan.push_back(0);
      pts->index.push_back(uint32_t(i));
    }
    scan.points = pts;
    m.scans.push_back(scan);
    s.missions.missions.push_back(m);
  }
  s.objects.missions = {"A", "B"};
  const Eigen::Vector3f centres[4] = {{-2, -2, 0.4f}, {2, 2, 0.4f}, {0, -3, 0.4f}, {1, -3, 0.4f}};
  const uint32_t mission_of[4] = {0, 1, 0, 1};
  for (int i = 0; i < 4; ++i) {
    lista::Object o;
    o.id = i;
    o.mission = mission_of[i];
    o.points = box_points(centres[i], 0.3f, 200, rng);
    o.update_geometry();
    s.objects.objects.push_back(o);
  }
  s.groups.method = "test";
  s.groups.object_ids = {0, 1, 2, 3};
  s.groups.group = {0, 1, 2, 2};
  s.groups.confidence = {0.9, 0.8, 0.95, 0.95};
  s.groups.count = 3;
  s.matches.objects = {change(0, lista::ChangeStatus::removed), change(1, lista::ChangeStatus::added),
                       change(2, lista::ChangeStatus::moved, 3), change(3, lista::ChangeStatus::moved, 2)};
  s.matches.objects[2].transform(0, 3) = 1.0;
  s.matches.objects[3].transform(0, 3) = -1.0;
  s.descriptors.method = "test";
  s.descriptors.object_ids = {0, 1, 2, 3};
  s.descriptors.values.resize(4, 3);
  s.descriptors.values << 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.1f, 0.99f;
  return s;
}

fs::path temp_dir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("lista_report_html_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct Capture : lista::Registrar {
  lista::StageInfo info;
  lista::StageFactory factory;
  void add(lista::StageInfo i, lista::StageFactory f) override {
    info = std::move(i);
    factory = std::move(f);
  }
};

// Creates the stage through the plugin's own manifest, as the core does.
Capture registered() {
  Capture capture;
  const lista::PluginManifest* m = lista_plugin_detail::manifest();
  EXPECT_EQ(m->sdk_version, LISTA_SDK_VERSION);
  m->register_stages(capture);
  return capture;
}

fs::path write_report(const Scene& s, const std::string& name, bool with_descriptors = true) {
  const fs::path dir = temp_dir(name);
  lista::BasicContext ctx("html");
  ctx.info.output_dir = dir.string();
  ctx.info.finished = {{"read", "io.missions", 0.5, 1 << 20}};
  ctx.info.jobs = 2;
  ctx.info.notes["describe"]["weights_sha256"] = "fe68557d";
  Capture plugin = registered();
  lista::Inputs in;
  in.set("missions", lista::Data::make(s.missions));
  in.set("objects", lista::Data::make(s.objects));
  in.set("groups", lista::Data::make(s.groups));
  in.set("matches", lista::Data::make(s.matches));
  if (with_descriptors) in.set("descriptors", lista::Data::make(s.descriptors));
  auto stage = plugin.factory(lista::Params::defaults(plugin.info.params));
  stage->run(in, ctx);
  return dir;
}

size_t count(const std::string& text, const std::string& needle) {
  size_t n = 0;
  for (size_t pos = text.find(needle); pos != std::string::npos; pos = text.find(needle, pos + 1)) ++n;
  return n;
}

}  // namespace

TEST(ReportHtml, RegistersUnderItsName) {
  Capture plugin = registered();
  EXPECT_EQ(plugin.info.name, "report.html");
  EXPECT_EQ(plugin.info.kind(), "report");
  ASSERT_NE(plugin.info.input("objects"), nullptr);
  EXPECT_TRUE(plugin.info.input("descriptors")->optional);
}

TEST(ReportHtml, WritesEveryPart) {
  const Scene s = make_scene();
  const fs::path dir = write_report(s, "parts");
  const std::string html = read(dir / "report.html");
  EXPECT_EQ(count(html, "<tr class=\"object-row\""), 4u);
  EXPECT_EQ(count(html, "<svg class=\"topdown\""), 1u);
  EXPECT_EQ(count(html, "<svg class=\"match-matrix\""), 1u);
  EXPECT_EQ(count(html, "<svg class=\"pca\""), 1u);
  EXPECT_EQ(count(html, "marker-end="), 1u) << "one arrow for the one moved pair";
  EXPECT_NE(html.find("data:image/png;base64,iVBORw0KGgo"), std::string::npos) << "embedded PNG";
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org")) << "no external resources";
  EXPECT_NE(html.find("removed: 1"), std::string::npos);
  EXPECT_NE(html.find("moved: 1 move (2 reports at their ends)"), std::string::npos) << "moves, not reports";
  EXPECT_NE(html.find("io.missions"), std::string::npos) << "stage timings";
  EXPECT_NE(html.find("<th>stages at once (-j)</th><td class=\"text\">2</td>"), std::string::npos);
  EXPECT_NE(html.find("<th>describe weights_sha256</th><td class=\"text\">fe68557d</td>"), std::string::npos)
      << "what stages noted (the weights a run used)";
  EXPECT_LT(html.find("<meta name=\"generator\" content=\"LiSTA report.html\">"), 4096u)
      << "the mark lista-run looks for before removing an earlier page";
  EXPECT_FALSE(fs::exists(dir / "report.html.tmp"));
  fs::remove_all(dir);
}

TEST(ReportHtml, WithoutDescriptorsUsesPhysicalDistanceAndNoPca) {
  const fs::path dir = write_report(make_scene(), "nodesc", false);
  const std::string html = read(dir / "report.html");
  EXPECT_EQ(count(html, "<svg class=\"pca\""), 0u);
  EXPECT_NE(html.find("physical distance"), std::string::npos);
  fs::remove_all(dir);
}

// An object a later stage added (history.static's copies) has no descriptor
// row: its cells say so instead of mixing metres into descriptor distances.
TEST(ReportHtml, ObjectWithoutADescriptorGetsNoSimilarity) {
  Scene s = make_scene();
  s.descriptors.object_ids = {0, 1, 2};
  s.descriptors.values.conservativeResize(3, 3);
  const fs::path dir = write_report(s, "partdesc");
  const std::string html = read(dir / "report.html");
  EXPECT_EQ(count(html, " vs 3: no descriptor"), 2u);  // rows 0 and 2 against column 3
  EXPECT_EQ(count(html, ": similarity "), 2u);
  EXPECT_EQ(html.find("\"nan"), std::string::npos) << "no NaN reached an attribute";
  EXPECT_NE(html.find("pale grey: an object without a descriptor"), std::string::npos);
  fs::remove_all(dir);
}

TEST(ReportHtml, ChangePlyHasOneVertexPerObjectPoint) {
  const Scene s = make_scene();
  const fs::path dir = write_report(s, "ply");
  const std::string ply = read(dir / "changes.ply");
  ASSERT_EQ(ply.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_NE(ply.find("element vertex 800\n"), std::string::npos);
  const size_t header_end = ply.find("end_header\n") + 11;
  EXPECT_EQ(ply.size() - header_end, 800u * (3 * 4 + 3 + 4 + 4 + 1));
  fs::remove_all(dir);
}

TEST(ReportHtml, NoOutputFolderIsAClearError) {
  Capture plugin = registered();
  lista::BasicContext ctx("html");
  lista::Inputs in;
  const Scene s = make_scene();
  in.set("missions", lista::Data::make(s.missions));
  in.set("objects", lista::Data::make(s.objects));
  auto stage = plugin.factory(lista::Params::defaults(plugin.info.params));
  try {
    stage->run(in, ctx);
    FAIL() << "expected an error";
  } catch (const lista::Error& e) {
    EXPECT_NE(std::string(e.what()).find("--out"), std::string::npos);
  }
}

// Opens the page in headless Chromium: the inline script must have run to the
// end (no error) and counted every object row in the rendered DOM.
TEST(ReportHtml, RendersInHeadlessChromium) {
  if (!fs::exists("/usr/bin/chromium")) {
    if (std::getenv("CI")) FAIL() << "chromium is not installed (setup.sh installs it)";
    GTEST_SKIP() << "chromium not installed";
  }
  const fs::path dir = write_report(make_scene(), "chromium");
  const fs::path profile = dir / "profile";
  const std::string cmd =
      "/usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync --user-data-dir=" +
      profile.string() + " --dump-dom file://" + (dir / "report.html").string() + " 2>/dev/null";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string dom;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) dom.append(buf, n);
  const int status = ::pclose(pipe);
  EXPECT_EQ(status, 0);
  EXPECT_NE(dom.find("data-rendered=\"ok\""), std::string::npos) << dom.substr(0, 400);
  EXPECT_NE(dom.find("data-objects=\"4\""), std::string::npos);
  fs::remove_all(dir);
}

// The table's motion is one move said once for both of its reports: the
// distance between the two centroids and the earlier object's signed turn,
// not the size of T's translation (which depends on where the frame's
// origin lies: here T turns about the origin only), with its direction.
TEST(ReportHtml, MotionIsTheCentroidsDisplacementAndTheSignedTurn) {
  Scene s = make_scene();
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  s.matches.objects[2].transform = T;
  s.matches.objects[3].transform = T.inverse();
  const double d = (s.objects.objects[3].centroid - s.objects.objects[2].centroid).norm();
  char expected[96];
  std::snprintf(expected, sizeof expected, "<td>%.2f m, -90.0&deg; A &rarr; B</td>", d);
  const fs::path dir = write_report(s, "motion");
  const std::string html = read(dir / "report.html");
  EXPECT_EQ(count(html, expected), 2u) << expected << " on both rows of the move";
  fs::remove_all(dir);
}

// A pose that fits as well turned (a symmetric shape) or slid is said on
// the row, with the turns and slides that fit, so that one number does not look certain.
TEST(ReportHtml, AmbiguousTurnIsSaidWithTheTurnsThatFit) {
  Scene s = make_scene();
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.block<3, 3>(0, 0) = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Eigen::Matrix4d twin = T;
  twin.block<3, 3>(0, 0) = Eigen::AngleAxisd(0.5 - M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Eigen::Matrix4d slid = T;  // the same turn, 0.3 m further along x
  slid(0, 3) += 0.3;
  s.matches.objects[2].transform = T;
  s.matches.objects[2].alternative_transforms = {twin, slid};
  s.matches.objects[3].transform = T.inverse();
  s.matches.objects[3].alternative_transforms = {twin.inverse(), slid.inverse()};
  const fs::path dir = write_report(s, "ambiguous");
  const std::string html = read(dir / "report.html");
  EXPECT_EQ(count(html, "28.6&deg; A &rarr; B; pose ambiguous, also fits -151.4&deg;, shifted 0.30 m</td>"), 2u);
  fs::remove_all(dir);
}

// Low confidence is seen, not only read: a dashed box on the map and a
// highlighted table cell; warnings come before the findings.
TEST(ReportHtml, LowConfidenceAndWarningsStandOut) {
  Scene s = make_scene();
  s.matches.objects[0].confidence = 0.3;  // the removed object
  s.matches.objects[1].confidence = 0.9;
  const fs::path dir = write_report(s, "low");
  const std::string html = read(dir / "report.html");
  EXPECT_EQ(count(html, "class=\"low-confidence\""), 1u);
  EXPECT_EQ(count(html, "<td class=\"low\">0.3"), 1u);
  EXPECT_NE(html.find("dashed box: confidence below 0.5"), std::string::npos);
  EXPECT_NE(html.find("class=\"axes\""), std::string::npos) << "coordinates on the map's edges";
  EXPECT_NE(html.find("<a href=\"#map-0\">A &rarr; B</a>"), std::string::npos) << "contents";
  EXPECT_NE(html.find("<h2 id=\"map-0\">"), std::string::npos);
  fs::remove_all(dir);
}

// A scan placed 1000 km away (a stray pose) widens the map, but the raster
// keeps to its pixel budget instead of taking gigabytes.
TEST(ReportHtml, AMapKilometresWideKeepsToItsPixels) {
  Scene s = make_scene();
  auto far = std::make_shared<lista::PointSet>(*s.missions.missions[1].scans[0].points);
  for (auto& p : far->xyz) p.x() += 1e6f;
  lista::Scan stray = s.missions.missions[1].scans[0];
  stray.points = far;
  s.missions.missions[1].scans.push_back(stray);
  const fs::path dir = write_report(s, "far");
  const std::string html = read(dir / "report.html");
  const std::string needle = "<svg class=\"topdown\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 ";
  const size_t at = html.find(needle);
  ASSERT_NE(at, std::string::npos);
  std::istringstream box(html.substr(at + needle.size(), 40));
  double width = 0, height = 0;
  box >> width >> height;
  EXPECT_GT(width, 0);
  EXPECT_LE(width, 1000.0 + 1) << html.substr(at, 120);
  EXPECT_LE(height, 1000.0 + 1);
  fs::remove_all(dir);
}

// What moved during a mission is drawn apart from the changes, as a dotted
// grey box on its pair's map, and counted in the summary; none, no mention.
TEST(ReportHtml, DynamicsAreDottedGreyBoxesApartFromTheChanges) {
  Scene s = make_scene();
  const fs::path none = write_report(s, "no_dynamics");
  EXPECT_EQ(read(none / "report.html").find("dynamic"), std::string::npos);
  lista::Dynamic d;
  d.mission = 1;
  d.points = 77;
  d.centroid = Eigen::Vector3f(1, 1, 0.8f);
  d.bbox_min = Eigen::Vector3f(0.8f, 0.8f, 0);
  d.bbox_max = Eigen::Vector3f(1.2f, 1.2f, 1.7f);
  s.objects.dynamics = {d};
  const fs::path dir = write_report(s, "dynamics");
  const std::string html = read(dir / "report.html");
  EXPECT_EQ(count(html, "class=\"dynamic\"><title>moved during mission B (77 points)"), 1u);
  EXPECT_NE(html.find("moved during their own mission (dynamic, not changes; dotted grey on the maps): 1"),
            std::string::npos);
  fs::remove_all(none);
  fs::remove_all(dir);
}

// Three missions: a box moved A -> B -> C (objects 2, 3, 4) and an object
// of B gone in C (5). Each map shows its own pair's changes only: the A -> B
// map has no 4 or 5, the B -> C map no 0, 1 or 2.
TEST(ReportHtml, EachChangeMapShowsOnlyItsPairsChanges) {
  Scene s = make_scene();
  lista::Mission c = s.missions.missions[1];
  c.name = "C";
  s.missions.missions.push_back(c);
  s.objects.missions = {"A", "B", "C"};
  std::mt19937 rng(3);
  for (const auto& [id, mission, centre] : std::vector<std::tuple<int, uint32_t, Eigen::Vector3f>>{
           {4, 2, {3, -3, 0.4f}}, {5, 1, {-3, 3, 0.4f}}}) {
    lista::Object o;
    o.id = id;
    o.mission = mission;
    o.points = box_points(centre, 0.3f, 200, rng);
    o.update_geometry();
    s.objects.objects.push_back(o);
  }
  s.groups.object_ids = {0, 1, 2, 3, 4, 5};
  s.groups.group = {0, 1, 2, 2, 2, 3};
  s.groups.confidence = {0.9, 0.8, 0.95, 0.95, 0.95, 0.9};
  s.matches.objects[3].match = 4;  // B's box moves on to C
  s.matches.objects.push_back(change(4, lista::ChangeStatus::moved, 3));
  s.matches.objects.push_back(change(5, lista::ChangeStatus::removed));
  const fs::path dir = write_report(s, "three", false);
  const std::string html = read(dir / "report.html");
  const size_t second = html.find("<svg class=\"topdown\"", html.find("<svg class=\"topdown\"") + 1);
  ASSERT_NE(second, std::string::npos) << "one map per consecutive pair";
  const std::string ab = html.substr(0, second), bc = html.substr(second);
  auto labelled = [](const std::string& map, int id) {
    return map.find("class=\"object-label\">" + std::to_string(id) + "</text>") != std::string::npos;
  };
  for (int id : {0, 2, 3}) EXPECT_TRUE(labelled(ab, id)) << id;  // A's removal, the A -> B move
  EXPECT_TRUE(labelled(ab, 1));                                   // B's arrival
  for (int id : {4, 5}) EXPECT_FALSE(labelled(ab, id)) << id;
  for (int id : {3, 4, 5}) EXPECT_TRUE(labelled(bc, id)) << id;  // the B -> C move, B's removal
  for (int id : {0, 2}) EXPECT_FALSE(labelled(bc, id)) << id;
  fs::remove_all(dir);

  // When the change points say B's object 5 changed against A as well (it
  // arrived in B and left before C), it is A -> B's arrival, in green, and
  // B -> C's removal, in red, though its one status is 'removed'.
  for (auto& o : s.objects.objects)
    if (o.id == 5) o.points.changed_against.assign(o.points.size(), lista::changed_against_either);
  // The box's chain A -> B -> C (the history matching gives) is in its rows.
  for (auto& c : s.matches.objects)
    if (c.object_id >= 2 && c.object_id <= 4) c.history = {2, 3, 4};
  const fs::path both = write_report(s, "three_both", false);
  const std::string html2 = read(both / "report.html");
  EXPECT_NE(html2.find("<td class=\"text\">2 A &rarr; 3 B &rarr; 4 C</td>"), std::string::npos);
  const size_t second2 = html2.find("<svg class=\"topdown\"", html2.find("<svg class=\"topdown\"") + 1);
  const std::string ab2 = html2.substr(0, second2), bc2 = html2.substr(second2);
  EXPECT_TRUE(labelled(ab2, 5));
  EXPECT_TRUE(labelled(bc2, 5));
  auto label_colour = [](const std::string& map, int id) {
    const size_t at = map.find("class=\"object-label\">" + std::to_string(id) + "</text>");
    const size_t fill = map.rfind("fill=\"", at);
    return map.substr(fill + 6, map.find('"', fill + 6) - fill - 6);
  };
  EXPECT_EQ(label_colour(ab2, 5), label_colour(ab2, 1)) << "arrival colour, as B's added object 1";
  EXPECT_NE(label_colour(ab2, 5), label_colour(bc2, 5));
  // Changed against C only: not in A -> B at all.
  for (auto& o : s.objects.objects)
    if (o.id == 5) o.points.changed_against.assign(o.points.size(), lista::changed_against_next);
  // The PCA plot gives each mission its own marker: C's objects triangles.
  s.descriptors.object_ids = {0, 1, 2, 3, 4, 5};
  s.descriptors.values.conservativeResize(6, 3);
  s.descriptors.values.bottomRows(2) << 0.5f, 0.5f, 0.7f, 0.2f, 0.9f, 0.4f;
  const fs::path next = write_report(s, "three_next", true);
  const std::string html3 = read(next / "report.html");
  const size_t second3 = html3.find("<svg class=\"topdown\"", html3.find("<svg class=\"topdown\"") + 1);
  EXPECT_NE(html3.find("shape: mission (circle A, square B, triangle C)"), std::string::npos);
  EXPECT_NE(html3.find("<polygon points="), std::string::npos);
  EXPECT_NE(html3.find("<title>object 4, C, group 2</title>"), std::string::npos);
  EXPECT_FALSE(labelled(html3.substr(0, second3), 5));
  EXPECT_TRUE(labelled(html3.substr(second3), 5));
  // Changed against neither (history.static's report of it standing still):
  // in no map, and counted apart in the summary.
  for (auto& o : s.objects.objects)
    if (o.id == 5) o.points.changed_against.assign(o.points.size(), 0);
  const fs::path still = write_report(s, "three_still", false);
  const std::string html4 = read(still / "report.html");
  EXPECT_EQ(html4.find("class=\"object-label\">5</text>"), std::string::npos);
  EXPECT_NE(html4.find("<span class=\"removed\">removed: 1</span>"), std::string::npos) << "A's 0 only";
  EXPECT_NE(html4.find("standing still before or after their change: 1"), std::string::npos);
  fs::remove_all(both);
  fs::remove_all(next);
  fs::remove_all(still);
}

// A row of removed boxes side by side: each id goes where it covers no
// other object's box and no other label (right of its box was the only
// spot, and there it sat on the neighbour's box).
TEST(ReportHtml, LabelsKeepOffOtherBoxes) {
  Scene s = make_scene();
  std::mt19937 rng(5);
  for (int k = 0; k < 3; ++k) {
    lista::Object o;
    o.id = 10 + k;
    o.mission = 0;
    o.points = box_points({-3.f + 0.62f * float(k), 2.f, 0.4f}, 0.3f, 200, rng);
    o.update_geometry();
    s.objects.objects.push_back(o);
    s.matches.objects.push_back(change(10 + k, lista::ChangeStatus::removed));
  }
  const fs::path dir = write_report(s, "labels", false);
  const std::string html = read(dir / "report.html");
  // Boxes: <rect x= y= width= height= fill="none" ...>; labels: <text x= y= font-size= ... class="object-label">.
  struct R { double x0, y0, x1, y1; };
  std::vector<R> boxes, labels;
  const std::regex box("<rect x=\"([-0-9.]+)\" y=\"([-0-9.]+)\" width=\"([-0-9.]+)\" height=\"([-0-9.]+)\" fill=\"none\"");
  const std::regex label("<text x=\"([-0-9.]+)\" y=\"([-0-9.]+)\" font-size=\"([0-9.]+)\"[^>]*class=\"object-label\">([0-9]+)<");
  const size_t end = html.find("</svg>");
  const std::string map = html.substr(0, end);
  for (std::sregex_iterator it(map.begin(), map.end(), box), e; it != e; ++it) {
    const double x = std::stod((*it)[1]), y = std::stod((*it)[2]);
    boxes.push_back({x, y, x + std::stod((*it)[3]), y + std::stod((*it)[4])});
  }
  std::vector<std::string> ids;
  for (std::sregex_iterator it(map.begin(), map.end(), label), e; it != e; ++it) {
    const double x = std::stod((*it)[1]), base = std::stod((*it)[2]), f = std::stod((*it)[3]);
    const std::string id = (*it)[4];
    labels.push_back({x, base - 0.8 * f, x + 0.6 * f * double(id.size()), base + 0.2 * f});
    ids.push_back(id);
  }
  ASSERT_EQ(boxes.size(), labels.size());
  ASSERT_GE(boxes.size(), 6u);
  auto overlap = [](const R& a, const R& b) { return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1; };
  for (size_t i = 0; i < labels.size(); ++i)
    for (size_t j = 0; j < boxes.size(); ++j)
      if (i != j) {
        EXPECT_FALSE(overlap(labels[i], boxes[j])) << "label " << ids[i] << " covers box " << j;
      }
  fs::remove_all(dir);
}
