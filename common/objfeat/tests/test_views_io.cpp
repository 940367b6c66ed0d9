// Reading `lista-sim views` folders: labels by shape across folders, splits,
// and one-line errors naming the file.
#include <lista_objfeat/views.hpp>

#include <lista/error.hpp>
#include <lista_io/pcd.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <unistd.h>
#include <utility>

namespace {

namespace fs = std::filesystem;

struct ViewEntry {
  ViewEntry(std::string shape_, std::string split_, std::string variant_ = "")
      : shape(std::move(shape_)), split(std::move(split_)), variant(std::move(variant_)) {}
  std::string shape, split, variant;  // variant: written only when not empty
};

// A views folder whose views are named by shape and split (3 points each);
// `shapes` is written as the index's "shapes" array when not empty.
fs::path write_folder(const std::string& name, const std::vector<ViewEntry>& views, const std::string& shapes = "") {
  const fs::path dir = fs::temp_directory_path() / ("lista_views_io_" + std::to_string(::getpid())) / name;
  fs::create_directories(dir / "views");
  std::string list;
  for (size_t i = 0; i < views.size(); ++i) {
    lista::PointSet p;
    p.xyz = {{0.f, 0.f, float(i)}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};
    p.intensity = {0.25f, 0.5f, 0.75f};
    p.label = {7, 7, 8};
    const std::string file = "views/" + std::to_string(i) + ".pcd";
    lista::io::write_scan_pcd((dir / file).string(), p, lista::io::PcdEncoding::binary);
    list += std::string(i ? "," : "") + "{\"file\": \"" + file + "\", \"instance\": " + std::to_string(i + 1) +
            ", \"shape\": \"" + views[i].shape + "\", \"split\": \"" + views[i].split + "\"" +
            (views[i].variant.empty() ? "" : ", \"variant\": \"" + views[i].variant + "\"") + "}";
  }
  std::ofstream(dir / "index.json") << "{\"format\": \"lista-views/1\", "
                                    << (shapes.empty() ? "" : "\"shapes\": [" + shapes + "], ") << "\"views\": ["
                                    << list << "]}";
  return dir;
}

TEST(ReadViews, ShapesKeepOneLabelAcrossFolders) {
  const fs::path a = write_folder("a", {{"crate-1", "train"}, {"cart-2", "test"}});
  const fs::path b = write_folder("b", {{"cart-2", "test"}, {"desk-3", "val"}, {"crate-1", "train"}});
  lista::objfeat::ViewSet set = lista::objfeat::read_views(std::vector<std::string>{a.string(), b.string()});
  ASSERT_EQ(set.views.size(), 5u);
  EXPECT_EQ(set.views[0].label, set.views[4].label);  // crate-1 in both folders
  EXPECT_EQ(set.views[1].label, set.views[2].label);  // cart-2
  EXPECT_NE(set.views[3].label, set.views[0].label);
  EXPECT_EQ(set.views[0].split, 0);
  EXPECT_EQ(set.views[1].split, 1);
  EXPECT_EQ(set.views[3].split, 1);  // val is held out too
  EXPECT_EQ(lista::objfeat::read_views(a.string()).views.size(), 2u);
  // One folder twice (here once through "x/../a") would make every view its
  // own copy's nearest neighbour: an error.
  const std::string again = (a.parent_path() / "x" / ".." / a.filename()).string();
  EXPECT_THROW(lista::objfeat::read_views(std::vector<std::string>{a.string(), b.string(), again}), lista::Error);
  fs::remove_all(a.parent_path());
}

// Labels never reach a reader's caller; xyz-only reads (training) keep the
// coordinates alone, with nothing held in reserve.
TEST(ReadViews, LabelsAreDroppedAndXyzOnlyKeepsTheCoordinatesAlone) {
  const fs::path a = write_folder("c", {{"crate-1", "train"}, {"cart-2", "test"}});
  const auto all = lista::objfeat::read_views(a.string());
  const auto xyz = lista::objfeat::read_views(a.string(), lista::objfeat::ViewChannels::xyz_only);
  ASSERT_EQ(all.views.size(), 2u);
  ASSERT_EQ(xyz.views.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const lista::PointSet& full = all.views[i].points;
    const lista::PointSet& bare = xyz.views[i].points;
    EXPECT_TRUE(full.label.empty());
    EXPECT_EQ(full.label.capacity(), 0u);
    EXPECT_EQ(full.intensity, (std::vector<float>{0.25f, 0.5f, 0.75f}));
    EXPECT_EQ(bare.xyz, full.xyz);
    EXPECT_TRUE(bare.intensity.empty() && bare.scan.empty() && bare.index.empty() && bare.label.empty());
    EXPECT_EQ(bare.intensity.capacity() + bare.scan.capacity() + bare.index.capacity(), 0u);
    EXPECT_EQ(xyz.views[i].label, all.views[i].label);
  }
  fs::remove_all(a.parent_path());
}

// Look-alike variants share a label but keep their own variant number; views
// without a variant (older folders) count as their shape's own.
TEST(ReadViews, VariantsNumberTheGeneratorsOwnIds) {
  const fs::path a = write_folder("v", {{"barrel-1", "test", "barrel-1"},
                                        {"barrel-1", "test", "barrel-4"},
                                        {"barrel-1", "test", "barrel-4"},
                                        {"crate-2", "test"}});
  const lista::objfeat::ViewSet set = lista::objfeat::read_views(a.string());
  ASSERT_EQ(set.views.size(), 4u);
  EXPECT_EQ(set.views[0].label, set.views[1].label);
  EXPECT_NE(set.views[0].variant, set.views[1].variant);
  EXPECT_EQ(set.views[1].variant, set.views[2].variant);
  EXPECT_NE(set.views[3].variant, set.views[0].variant);
  EXPECT_NE(set.views[3].variant, set.views[1].variant);
  fs::remove_all(a.parent_path());
}

// Sources come from the shapes list, numbered across folders; shapes without
// one (or folders without a list) are "unknown".
TEST(ReadViews, SourcesComeFromTheShapesList) {
  const fs::path a = write_folder("s1", {{"chair-1", "train"}, {"sh3d/bed", "train"}},
                                  R"({"id": "chair-1", "source": "procedural"}, {"id": "sh3d/bed", "source": "sweethome3d"})");
  const fs::path b = write_folder("s2", {{"sh3d/desk", "train"}, {"crate-2", "train"}},
                                  R"({"id": "sh3d/desk", "source": "sweethome3d"}, {"id": "crate-2"})");
  const fs::path c = write_folder("s3", {{"cart-3", "train"}});
  const lista::objfeat::ViewSet set = lista::objfeat::read_views(std::vector<std::string>{a.string(), b.string(), c.string()});
  ASSERT_EQ(set.views.size(), 5u);
  ASSERT_EQ(set.sources, (std::vector<std::string>{"procedural", "sweethome3d", "unknown"}));
  EXPECT_EQ(set.views[0].source, 0);
  EXPECT_EQ(set.views[1].source, 1);
  EXPECT_EQ(set.views[2].source, 1);
  EXPECT_EQ(set.views[3].source, 2);
  EXPECT_EQ(set.views[4].source, 2);
  lista::objfeat::ViewSet train, test;
  lista::objfeat::split_by_shape(set, 0.0, 1, train, test);
  EXPECT_EQ(train.sources, set.sources);
  fs::remove_all(a.parent_path());
}

// Sizes come from the shapes list, sensor and distance from each view; what
// a folder does not give stays unknown ("" or NaN); a malformed size is an
// error naming the file and the shape.
TEST(ReadViews, SizesSensorsAndDistancesAreKeptForBreakdowns) {
  const fs::path a = write_folder("e1", {{"box-1", "train"}, {"box-2", "test"}, {"box-1", "train"}},
                                  R"({"id": "box-1", "extent": [0.5, 0.25, 1.5]}, {"id": "box-2"})");
  {  // give the first view a sensor and a distance
    std::ifstream in(a / "index.json");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string first = "\"instance\": 1,";
    text.replace(text.find(first), first.size(), first + " \"sensor\": \"vlp16\", \"distance\": 4.5,");
    std::ofstream(a / "index.json") << text;
  }
  const lista::objfeat::ViewSet set = lista::objfeat::read_views(a.string());
  ASSERT_EQ(set.views.size(), 3u);
  EXPECT_EQ(set.views[0].extent, (std::array<float, 3>{0.5f, 0.25f, 1.5f}));
  EXPECT_EQ(set.views[2].extent, set.views[0].extent);
  for (float e : set.views[1].extent) EXPECT_TRUE(std::isnan(e));
  EXPECT_EQ(set.views[0].sensor, "vlp16");
  EXPECT_FLOAT_EQ(set.views[0].distance, 4.5f);
  EXPECT_EQ(set.views[1].sensor, "");
  EXPECT_TRUE(std::isnan(set.views[1].distance));
  for (const std::string bad : {"[0.5, 0.0, 1.5]", "\"big\"", "[0.5, \"wide\", 1.5]", "[0.5, 1.5]"}) {
    const fs::path b = write_folder("e2", {{"box-1", "train"}}, R"({"id": "box-1", "extent": )" + bad + "}");
    try {
      lista::objfeat::read_views(b.string());
      ADD_FAILURE() << "extent " << bad << " was accepted";
    } catch (const lista::Error& e) {
      EXPECT_NE(std::string(e.what()).find("index.json: shape 'box-1' extent must be three positive sizes"),
                std::string::npos)
          << e.what();
    }
  }
  {  // a distance that is not a number
    std::ifstream in(a / "index.json");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string number = "\"distance\": 4.5";
    text.replace(text.find(number), number.size(), "\"distance\": \"far\"");
    std::ofstream(a / "index.json") << text;
  }
  try {
    lista::objfeat::read_views(a.string());
    ADD_FAILURE() << "a distance of \"far\" was accepted";
  } catch (const lista::Error& e) {
    EXPECT_NE(std::string(e.what()).find("index.json: view 'views/0.pcd' distance must be a number (metres)"),
              std::string::npos)
        << e.what();
  }
  fs::remove_all(a.parent_path());
}

TEST(ReadViews, MissingOrMalformedFoldersAreErrorsNamingTheFile) {
  const fs::path a = write_folder("c", {{"crate-1", "train"}});
  auto expect_error = [](const std::vector<std::string>& folders, const std::string& words) {
    try {
      lista::objfeat::read_views(folders);
      ADD_FAILURE() << "expected an error mentioning " << words;
    } catch (const lista::Error& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  expect_error({a.string(), "/nonexistent/views"}, "/nonexistent/views/index.json: not found");
  expect_error({}, "no views folder");
  std::ofstream(a / "index.json") << "{\"format\": \"lista-views/9\"}";
  expect_error({a.string()}, "format is not");
  // A hand-made index with a field missing or of the wrong kind: the field
  // and the view named in plain words, never the JSON library's.
  const std::string head = "{\"format\": \"lista-views/1\", ";
  for (const auto& [index, words] : std::vector<std::pair<std::string, std::string>>{
           {"[1, 2]", "index.json: must be a JSON object"},
           {head + "\"views\": \"x\"}", "index.json: \"views\" must be a list of views"},
           {head + "\"views\": [{\"file\": \"0.pcd\", \"instance\": 0}]}", "view 0 needs \"shape\" as text"},
           {head + "\"views\": [{\"file\": \"0.pcd\", \"shape\": 5, \"instance\": 0}]}", "view 0 needs \"shape\" as text"},
           {head + "\"views\": [{\"file\": \"0.pcd\", \"shape\": \"s\"}]}", "view 0 needs \"instance\" as a whole number"},
           {head + "\"shapes\": [{\"class\": \"box\"}], \"views\": []}", "shape 0 needs \"id\" as text"}}) {
    std::ofstream(a / "index.json") << index;
    expect_error({a.string()}, words);
  }
  fs::remove_all(a.parent_path());
}

}  // namespace
