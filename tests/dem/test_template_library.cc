// The shipped template library (dem/samples/template_library.h, cases/templates/ballast/): it loads
// with both mass sources, its manifest matches a fresh computation, and bad manifests are refused.
#include "dem/samples/template_library.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/input_error.h"
#include "dem/io/csv_table.h"
#include "dem/samples/closed_surface.h"
#include "input_error_message.h"

namespace trackbed::dem {
namespace {

namespace fs = std::filesystem;

const std::string kLibrary = std::string(TRACKBED_SOURCE_DIR) + "/cases/templates/ballast";
const std::string kManifest = kLibrary + "/library.csv";

using testing::contains;
using testing::input_error_message;

// The manifest stores 8 significant digits: a relative rounding of at most 5e-8.
void expect_stored(double stored, double computed, const std::string& what) {
  EXPECT_NEAR(stored, computed, 1e-7 * std::abs(computed)) << what;
}

TEST(TemplateLibrary, LoadsBothSettingsWithEitherMassSource) {
  double mean_count[2] = {0, 0};
  int setting_index = 0;
  for (const char* setting : {"D120R0.5", "D130R0.4"}) {
    const auto surface = read_template_library(kManifest, setting, MassSource::surface);
    const auto pebbles = read_template_library(kManifest, setting, MassSource::pebbles);
    ASSERT_GE(surface.size(), 20u) << setting;
    ASSERT_EQ(surface.size(), pebbles.size());
    for (std::size_t i = 0; i < surface.size(); ++i) {
      const LibraryTemplate& t = surface[i];
      EXPECT_EQ(t.setting, setting);
      EXPECT_GE(t.sieve_size, 0.0224);
      EXPECT_LE(t.sieve_size, 0.063);
      EXPECT_EQ(t.sieve_size, t.shape.sieve_size);
      // The pebbles lie inside the stone: their union is smaller than its surface.
      EXPECT_LT(pebbles[i].clump.volume, t.clump.volume) << t.clump.name;
      EXPECT_EQ(pebbles[i].clump.spheres.size(), t.clump.spheres.size());
      EXPECT_GT(t.clump.bounding_radius, 0.0);
      mean_count[setting_index] += static_cast<double>(t.clump.spheres.size()) / surface.size();
    }
    ++setting_index;
  }
  EXPECT_GT(mean_count[1], mean_count[0]);  // D130/R0.4 is the finer setting
}

// Pack the first stone again from its STL at each of its settings: the manifest row, the pebble
// file and the surface-source template all match.
TEST(TemplateLibrary, ManifestMatchesAFreshComputation) {
  const CsvTable manifest(kManifest);
  for (int row = 0; row < 2; ++row) {
    const std::string name = manifest.text(row, "name");
    const TriangleMesh surface =
        read_closed_surface(kLibrary + "/" + manifest.text(row, "surface"));
    BubblePackSettings pack = parse_setting(manifest.text(row, "setting"), BubblePackSettings());
    pack.resolution = static_cast<int>(manifest.number(row, "resolution"));
    const BubblePackResult p = bubble_pack(surface, pack, name);
    const ShapeIndices s = shape_indices(surface);

    EXPECT_EQ(manifest.number(row, "pebble_count"), p.pebble_count()) << name;
    expect_stored(manifest.number(row, "min_radius"), p.min_radius, name);
    expect_stored(manifest.number(row, "max_radius"), p.max_radius, name);
    expect_stored(manifest.number(row, "volume_error"), p.volume_error, name);
    expect_stored(manifest.number(row, "inertia_error"), p.inertia_error, name);
    expect_stored(manifest.number(row, "surface_volume"), p.surface_mass.volume, name);
    expect_stored(manifest.number(row, "longest"), s.longest, name);
    expect_stored(manifest.number(row, "intermediate"), s.intermediate, name);
    expect_stored(manifest.number(row, "shortest"), s.shortest, name);
    expect_stored(manifest.number(row, "elongation"), s.elongation, name);
    expect_stored(manifest.number(row, "flatness"), s.flatness, name);
    expect_stored(manifest.number(row, "sphericity"), s.sphericity, name);
    expect_stored(manifest.number(row, "angularity"), s.angularity, name);
    EXPECT_EQ(manifest.number(row, "faces"), s.faces) << name;
    expect_stored(manifest.number(row, "sieve_size"), s.sieve_size, name);

    // The pebble file holds the same pebbles (9 digits; 1e-8 of the stone's size).
    const CsvTable file(kLibrary + "/" + manifest.text(row, "pebbles"));
    ASSERT_EQ(file.num_rows(), p.pebble_count());
    for (int i = 0; i < file.num_rows(); ++i) {
      const Vec3 c(file.number(i, "x"), file.number(i, "y"), file.number(i, "z"));
      EXPECT_LT((c - p.pebbles[i].centre).norm(), 1e-8 * s.longest) << name << " " << i;
      EXPECT_NEAR(file.number(i, "radius"), p.pebbles[i].radius, 1e-8 * s.longest);
    }
    const auto library =
        read_template_library(kManifest, manifest.text(row, "setting"), MassSource::surface);
    EXPECT_NEAR(library[0].clump.volume, p.clump.volume, 1e-12 * p.clump.volume);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(library[0].clump.principal_moments[k], p.clump.principal_moments[k],
                  1e-9 * p.clump.principal_moments[k]);
    }
  }
}

// A manifest of its own per test, next to copies of two library files, removed afterwards.
class BadManifest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("trackbed_library_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    for (const char* f : {"stone01.stl", "stone01-D120R0.5.csv"}) {
      fs::copy_file(kLibrary + "/" + f, dir_ / f, fs::copy_options::overwrite_existing);
    }
    std::ifstream in(kManifest);
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("name,", 0) == 0) header_ = line;
      if (line.rfind("stone01-D120R0.5,", 0) == 0) row_ = line;
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes the header and `row` (line 2) and returns the error reading setting D120R0.5.
  std::string error_reading(const std::string& row, const std::string& setting = "D120R0.5") {
    const std::string path = (dir_ / "library.csv").string();
    std::ofstream(path) << header_ << "\n" << row << "\n";
    return input_error_message([&] { read_template_library(path, setting, MassSource::surface); });
  }
  // The row with the field of `column` set to `value`.
  std::string with_field(const std::string& column, const std::string& value) const {
    std::vector<std::string> names = split(header_), fields = split(row_);
    const auto at = std::find(names.begin(), names.end(), column) - names.begin();
    fields.at(at) = value;
    std::string r;
    for (const std::string& f : fields) r += (r.empty() ? "" : ",") + f;
    return r;
  }
  std::string field(const std::string& column) const {
    const std::vector<std::string> names = split(header_), fields = split(row_);
    return fields.at(std::find(names.begin(), names.end(), column) - names.begin());
  }
  static std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream s(line);
    std::string f;
    while (std::getline(s, f, ',')) out.push_back(f);
    return out;
  }

  fs::path dir_;
  std::string header_, row_;
};

TEST_F(BadManifest, UnknownSettingListsTheKnownOnes) {
  const std::string e = error_reading(row_, "D150R0.3");
  EXPECT_TRUE(contains(e, "setting 'D150R0.3' is not in the library; known settings: D120R0.5"))
      << e;
}

TEST_F(BadManifest, MissingFilesNameTheLine) {
  std::string e = error_reading(with_field("pebbles", "gone.csv"));
  EXPECT_TRUE(contains(e, "library.csv:2: pebbles file 'gone.csv' not found")) << e;
  e = error_reading(with_field("surface", "gone.stl"));
  EXPECT_TRUE(contains(e, "library.csv:2: surface file 'gone.stl' not found")) << e;
}

TEST_F(BadManifest, MalformedRowsNameTheLine) {
  std::string e = error_reading(with_field("faces", "many"));
  EXPECT_TRUE(contains(e, "library.csv:2:")) << e;
  EXPECT_TRUE(contains(e, "'many'")) << e;
  e = error_reading(with_field("sieve_size", "-0.04"));
  EXPECT_TRUE(contains(e, "library.csv:2: sieve_size '-0.04'")) << e;
  e = error_reading(row_ + ",extra");
  EXPECT_TRUE(contains(e, "library.csv:2:")) << e;
  const int count = std::stoi(field("pebble_count"));
  e = error_reading(with_field("pebble_count", std::to_string(count + 1)));
  EXPECT_TRUE(contains(e, "library.csv:2: pebble_count " + std::to_string(count + 1) +
                              " but 'stone01-D120R0.5.csv' holds " + std::to_string(count)))
      << e;
}

TEST(TemplateLibrary, SettingNames) {
  BubblePackSettings s;
  s.distance = 130.0;
  s.ratio = 0.4;
  EXPECT_EQ(setting_name(s), "D130R0.4");
  const BubblePackSettings back = parse_setting("D130R0.4", BubblePackSettings());
  EXPECT_EQ(back.distance, 130.0);
  EXPECT_EQ(back.ratio, 0.4);
  for (const char* bad : {"130R0.4", "D130", "D13xR0.4", "DR0.4", "D130R"}) {
    EXPECT_THROW(parse_setting(bad, BubblePackSettings()), InputError) << bad;
  }
}

}  // namespace
}  // namespace trackbed::dem
