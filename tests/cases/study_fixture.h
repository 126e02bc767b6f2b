// The fixture of the tests that run one of the paper's studies at small scale as a user runs it
// (cases/<study>/small/): the samples built by build-sample from the shipped sample files into
// TRACKBED_STUDY_WORK/samples, the shipped cases run on them into TRACKBED_STUDY_WORK/runs, and
// each run's summary checked against the study's stored reference figures.
// ctest runs each test alone, in the order its fixtures give (tests/cases/CMakeLists.txt): the
// samples and runs are kept for the tests that follow.
#pragma once

#include <map>
#include <string>
#include <utility>

#include "cli_fixture.h"

class Study : public Cli {
 protected:
  // `study`: the folder in cases/ (and the reference tests/cases/reference/<study>_small.csv);
  // `base`: the ball sample file in cases/samples/ the others convert; `sample_of`: the sample
  // each model of the study runs on.
  Study(std::string study, std::string base, std::map<std::string, std::string> sample_of)
      : study_(std::move(study)), base_(std::move(base)), sample_of_(std::move(sample_of)) {}

  const std::map<std::string, std::string>& sample_of() const { return sample_of_; }
  fs::path sample(const std::string& name) const { return work_ / "samples" / name; }
  fs::path results(const std::string& model) const { return work_ / "runs" / model; }
  // The shipped small case file of `model`.
  std::string small_case(const std::string& model) const {
    return source_ + "/cases/" + study_ + "/small/" + model + ".prm";
  }

  void build_base_sample() {
    const Result r = run("build-sample " + source_ + "/cases/samples/" + base_ +
                         ".prm --threads 1 --output " + sample(base_).string());
    ASSERT_EQ(r.code, 0) << r.out << r.err;
  }
  // The shipped sample file `name` on the base sample of the work folder (its templates stay
  // the shipped file's: a relative name resolves against the file that sets it). A pilot zone's
  // run is `pilot_run` of the work folder (pilot_zone_of).
  void build_converted_sample(const std::string& name, const std::string& pilot_run = "") {
    const std::string file = source_ + "/cases/samples/" + name + ".prm";
    const Result r = run_including(
        "build-sample", file,
        "subsection zone\n  set base sample = " + (sample(base_) / "sample.h5").string() +
            (pilot_run.empty() ? "" : "\n  set clump zone = " + pilot_zone_of(file, pilot_run)) +
            "\nend\n"
            "subsection output\n  set plot = false\n  set vtu = false\nend\n",
        sample(name));
    ASSERT_EQ(r.code, 0) << r.out << r.err;
  }
  // Runs the shipped small case of `model` on its sample, checks that it finished and returns its
  // results folder (checks that need it come after, then check_reference_of(model)). With `plot`
  // the run draws its pictures as a user's run does ('output/plot'), and none of them may fail.
  // `variant`: case-file text added after the case's, the run then written to results(variant
  // name) instead.
  fs::path run_model(const std::string& model, bool plot = false,
                     const std::pair<std::string, std::string>& variant = {}) {
    const fs::path out = results(variant.first.empty() ? model : variant.first);
    const Result r =
        run_including("run", small_case(model),
                      "subsection particles\n  set sample file = " +
                          (sample(sample_of_.at(model)) / "sample.h5").string() +
                          "\nend\nsubsection output\n  set plot = " + (plot ? "true" : "false") +
                          "\nend\n" + variant.second,
                      out);
    EXPECT_EQ(r.code, 0) << r.out << r.err;
    EXPECT_EQ(r.out.find("the plot failed"), std::string::npos) << r.out;
    EXPECT_TRUE(fs::exists(out / "push.csv"));
    EXPECT_NE(slurp(out / "summary.json").find("\"status\": \"finished\""), std::string::npos);
    return out;
  }
  // The clump zone of sample file `file`, a pilot(FOLDER, ...) term, with its pilot run's folder
  // replaced by the results of `model` in the work folder.
  std::string pilot_zone_of(const std::string& file, const std::string& model) const {
    std::smatch m;
    const std::string text = slurp(file);
    const std::regex zone(R"(set clump zone\s*=\s*pilot\([^,]*(,[^)]*\)))");
    EXPECT_TRUE(std::regex_search(text, m, zone)) << file << ": no pilot(...) clump zone";
    return "pilot(" + results(model).string() + m[1].str();
  }
  void check_reference_of(const std::string& model) {
    check_reference(source_ + "/tests/cases/reference/" + study_ + "_small.csv", model,
                    results(model));
  }

 private:
  const fs::path work_ = TRACKBED_STUDY_WORK;
  const std::string source_ = TRACKBED_SOURCE_DIR;
  std::string study_, base_;
  std::map<std::string, std::string> sample_of_;
};
