// Clump templates: the principal frame, geometric scaling and the CSV reader with its errors.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "common/input_error.h"
#include "dem/engine/clump_template.h"
#include "dem/io/clump_template_file.h"

namespace trackbed::dem {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Four spheres in a skewed, shifted frame with three clearly different principal moments, so the
// principal axes are well defined.
std::vector<SphereShape> skewed_clump() {
  const Mat3 rotation = Eigen::AngleAxisd(1.1, Vec3(0.3, 1.0, -0.6).normalized()).matrix();
  const Vec3 shift(0.4, 0.2, -1.3);
  const std::vector<SphereShape> local = {{Vec3(-0.020, 0.000, 0.000), 0.016},
                                          {Vec3(0.000, 0.002, 0.000), 0.018},
                                          {Vec3(0.022, -0.004, 0.003), 0.014},
                                          {Vec3(0.004, 0.012, 0.002), 0.010}};
  std::vector<SphereShape> out;
  for (const SphereShape& sp : local) out.push_back({rotation * sp.centre + shift, sp.radius});
  return out;
}

double relative(double value, double reference) {
  return std::abs(value - reference) / std::abs(reference);
}

TEST(ClumpTemplate, SingleSphereTemplateIsExact) {
  const double r = 0.025;
  const ClumpTemplate t = make_clump_template("ball", {{Vec3(1.0, 2.0, 3.0), r}});
  const double v = 4.0 / 3.0 * kPi * r * r * r;
  EXPECT_EQ(t.name, "ball");
  ASSERT_EQ(t.spheres.size(), 1u);
  EXPECT_LT(t.spheres[0].centre.norm(), 1e-15);
  EXPECT_NEAR(t.volume, v, 1e-14 * v);
  EXPECT_NEAR(t.bounding_radius, r, 1e-15);
  EXPECT_NEAR(t.equivalent_radius(), r, 1e-15);
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(t.principal_moments(k), 0.4 * v * r * r, 1e-14 * v * r * r);
}

TEST(ClumpTemplate, SpheresAreInThePrincipalFrame) {
  const std::vector<SphereShape> input = skewed_clump();
  const ClumpTemplate t = make_clump_template("skewed", input);
  ASSERT_EQ(t.spheres.size(), input.size());

  // The template's own spheres have their centroid at the origin and a diagonal inertia with
  // the template's moments. Both integrations meet the 1e-4 tolerance, hence 2e-4 between them.
  const MassProperties mp = sphere_union_mass_properties(t.spheres);
  const double size = t.bounding_radius;
  EXPECT_LT(mp.centroid.norm(), 2e-4 * size);
  const double trace = mp.inertia.trace();
  EXPECT_LT(std::abs(mp.inertia(0, 1)), 2e-4 * trace);
  EXPECT_LT(std::abs(mp.inertia(0, 2)), 2e-4 * trace);
  EXPECT_LT(std::abs(mp.inertia(1, 2)), 2e-4 * trace);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(relative(mp.inertia(k, k), t.principal_moments(k)), 2e-4) << "axis " << k;
  }
  EXPECT_LT(relative(mp.volume, t.volume), 2e-4);

  // A rigid motion: radii and the distances between centres are unchanged.
  for (std::size_t i = 0; i < input.size(); ++i) {
    EXPECT_EQ(t.spheres[i].radius, input[i].radius);
    for (std::size_t k = 0; k < i; ++k) {
      EXPECT_NEAR((t.spheres[i].centre - t.spheres[k].centre).norm(),
                  (input[i].centre - input[k].centre).norm(), 1e-15);
    }
  }
  double reach = 0.0;
  for (const SphereShape& sp : t.spheres) reach = std::max(reach, sp.centre.norm() + sp.radius);
  EXPECT_DOUBLE_EQ(t.bounding_radius, reach);
  EXPECT_NEAR(t.equivalent_radius(), std::cbrt(3.0 * t.volume / (4.0 * kPi)), 1e-15);
  EXPECT_LT(t.principal_moments(0), t.principal_moments(1));
  EXPECT_LT(t.principal_moments(1), t.principal_moments(2));
}

TEST(ClumpTemplate, ScaledScalesLengthsVolumeAndMoments) {
  const ClumpTemplate t = make_clump_template("skewed", skewed_clump());
  const double f = 2.5;
  const ClumpTemplate s = scaled(t, f);
  EXPECT_EQ(s.name, t.name);
  EXPECT_NEAR(s.volume, t.volume * f * f * f, 1e-14 * s.volume);
  EXPECT_NEAR(s.bounding_radius, t.bounding_radius * f, 1e-15);
  EXPECT_NEAR(s.equivalent_radius(), t.equivalent_radius() * f, 1e-14);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(s.principal_moments(k), t.principal_moments(k) * std::pow(f, 5),
                1e-14 * s.principal_moments(k));
  }
  for (std::size_t i = 0; i < t.spheres.size(); ++i) {
    EXPECT_LT((s.spheres[i].centre - f * t.spheres[i].centre).norm(), 1e-15);
    EXPECT_NEAR(s.spheres[i].radius, f * t.spheres[i].radius, 1e-15);
  }
  // Agrees with integrating the scaled shape afresh, within twice the tolerance.
  const ClumpTemplate fresh = make_clump_template("fresh", s.spheres);
  EXPECT_LT(relative(fresh.volume, s.volume), 2e-4);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LT(relative(fresh.principal_moments(k), s.principal_moments(k)), 2e-4);
  }
  for (double bad : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    EXPECT_THROW(scaled(t, bad), InputError);
  }
}

// Writes `text` to a fresh file in the test temporary directory and returns its path.
std::string write_file(const std::string& name, const std::string& text) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("trackbed_test_clump_template_" + name + ".csv"))
          .string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(ClumpTemplate, CsvRoundTripGivesTheSameTemplate) {
  const std::vector<SphereShape> spheres = skewed_clump();
  // Columns in another order, an extra column, comments, blank lines and a CRLF line ending.
  std::string text = "# scanned stone 7, metres\n\nradius, z ,label,x,y\n";
  for (std::size_t i = 0; i < spheres.size(); ++i) {
    char row[200];
    std::snprintf(row, sizeof row, "%.17g,%.17g,pebble %zu,%.17g,%.17g%s\n", spheres[i].radius,
                  spheres[i].centre.z(), i, spheres[i].centre.x(), spheres[i].centre.y(),
                  i == 1 ? "\r" : "");
    text += row;
    if (i == 1) text += "   # a comment between rows\n\n";
  }
  const ClumpTemplate read = read_clump_template_csv(write_file("round_trip", text), "stone7");
  const ClumpTemplate made = make_clump_template("stone7", spheres);
  EXPECT_EQ(read.name, "stone7");
  ASSERT_EQ(read.spheres.size(), made.spheres.size());
  for (std::size_t i = 0; i < made.spheres.size(); ++i) {
    EXPECT_EQ(read.spheres[i].centre, made.spheres[i].centre);
    EXPECT_EQ(read.spheres[i].radius, made.spheres[i].radius);
  }
  EXPECT_EQ(read.volume, made.volume);
  EXPECT_EQ(read.principal_moments, made.principal_moments);
  EXPECT_EQ(read.bounding_radius, made.bounding_radius);
}

// The message of the InputError that reading `text` throws, or a test failure.
std::string csv_error(const std::string& name, const std::string& text) {
  const std::string path = write_file(name, text);
  try {
    read_clump_template_csv(path, name);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << name;
  return "";
}

// Checks that `message` starts with "PATH:LINE: " and contains `what`.
void expect_error_at(const std::string& name, int line, const std::string& message,
                     const std::string& what) {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("trackbed_test_clump_template_" + name + ".csv"))
          .string();
  const std::string where = path + ":" + std::to_string(line) + ": ";
  EXPECT_EQ(message.rfind(where, 0), 0u) << message << "\nexpected to start with " << where;
  EXPECT_NE(message.find(what), std::string::npos) << message << "\nexpected: " << what;
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
}

TEST(ClumpTemplate, CsvErrorsNameFileAndLine) {
  const std::string header = "# test\nx,y,z,radius\n";
  expect_error_at("missing_column", 2, csv_error("missing_column", "# test\nx,y,radius\n0,0,1\n"),
                  "no column 'z'");
  expect_error_at("duplicate_column", 1, csv_error("duplicate_column", "x,y,z,radius,x\n"),
                  "column 'x' appears twice");
  expect_error_at("non_numeric", 4, csv_error("non_numeric", header + "0,0,0,0.01\n0,abc,0,0.01\n"),
                  "column 'y': 'abc' is not valid; it must be a finite number");
  expect_error_at("empty_field", 3, csv_error("empty_field", header + "0,,0,0.01\n"),
                  "column 'y': '' is not valid");
  expect_error_at("not_finite", 3, csv_error("not_finite", header + "inf,0,0,0.01\n"),
                  "column 'x': 'inf' is not valid");
  expect_error_at("too_few_fields", 3, csv_error("too_few_fields", header + "0,0,0.01\n"),
                  "row has 3 fields but the header (line 2) has 4");
  expect_error_at("trailing_comma", 3, csv_error("trailing_comma", header + "0,0,0,0.01,\n"),
                  "row has 5 fields");
  expect_error_at("zero_radius", 5, csv_error("zero_radius", header + "0,0,0,0.01\n\n0,0,0.01,0\n"),
                  "radius 0 is not valid; a sphere radius must be > 0");
  expect_error_at("negative_radius", 3, csv_error("negative_radius", header + "0,0,0,-0.02\n"),
                  "radius -0.02 is not valid");
  expect_error_at("nan_radius", 3, csv_error("nan_radius", header + "0,0,0,nan\n"),
                  "column 'radius': 'nan' is not valid");
  expect_error_at("no_rows", 2, csv_error("no_rows", header + "# nothing yet\n"),
                  "has no spheres after the header");
  expect_error_at("no_header", 2, csv_error("no_header", "# only a comment\n\n"),
                  "has no header line");
  expect_error_at("empty_file", 1, csv_error("empty_file", ""), "has no header line");

  const std::string missing =
      (std::filesystem::temp_directory_path() / "trackbed_no_such_template.csv").string();
  std::filesystem::remove(missing);
  try {
    read_clump_template_csv(missing, "ghost");
    ADD_FAILURE() << "no InputError for a missing file";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(missing + ": cannot open", 0), 0u) << message;
  }
}

TEST(ClumpTemplate, InvalidSpheresNameTheTemplate) {
  try {
    make_clump_template("bad", {{Vec3::Zero(), 0.01}, {Vec3::Zero(), -1.0}});
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("clump template 'bad': clump sphere 2 of 2", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace trackbed::dem
