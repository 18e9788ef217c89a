// The `render` and `report` subcommands: options are checked here (so `skred render --help`
// works without Python) and passed on to python/skred-post.py (python_post.hpp).
// Included by main.cpp only (it needs CLI11).
#pragma once
#include <fmt/core.h>
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "app/python_post.hpp"

namespace skred {

class PostCommands {
 public:
  explicit PostCommands(CLI::App& app) {
    render_ =
        app.add_subcommand("render", "Draw results: PNG of one frame, every frame + GIF, or the series");
    render_->add_option("outdir", outdir_, "Output folder of `skred run`")
        ->required()
        ->check(CLI::ExistingDirectory);
    render_->add_option(
        "--field", field_,
        "Colour field NAME or NAME:COMPONENT, e.g. stress:yy, smoothed_p (default: displacement magnitude)");
    auto* step = render_->add_option("--step", step_, "Frame number (default: the last)");
    auto* all = render_->add_flag("--all", all_, "Render every frame and assemble an animated GIF");
    auto* series = render_->add_flag("--series", series_, "Plot series.csv (energies, speeds, momentum)");
    step->excludes(all)->excludes(series);
    all->excludes(series);
    render_->add_option("-o,--output", output_, "Output file (default: OUTDIR/pictures/...)");
    render_->add_flag("--arrows", arrows_, "Velocity arrows on a subsample (Post fig. 9)");
    render_->add_flag("--crosses", crosses_, "Principal-stress crosses on a subsample (Post fig. 12)");
    render_->add_flag("--slip-circle", slip_circle_,
                      "Draw summary.json's limit-equilibrium slip circle (Bishop's, a 2D slope of one soil)");
    auto* stripes = render_->add_flag("--stripes", stripes_, "Colour by body with stripes (Post §5.2)");
    auto* checker = render_->add_flag("--checkerboard", checker_, "Colour by body with a checkerboard");
    stripes->excludes(checker);
    render_->add_option("--pattern-width", pattern_width_, "Stripe/square width [m] (default 4 voxels)")
        ->check(CLI::PositiveNumber);
    render_->add_option("--pattern-angle", pattern_angle_, "Stripe direction [degrees from x]");
    render_
        ->add_option("--range", range_, "Colour range MIN MAX, in the colour bar's unit (kPa for stresses)")
        ->expected(2);
    render_->add_option("--cmap", cmap_, "matplotlib colour map (default viridis)");
    render_->add_option("--sample", sample_, "Overlays: one particle per N x N voxels (default 4)")
        ->check(CLI::Range(1, 1000));
    render_->add_option("--fps", fps_, "Frames per second of the GIF (default 8)")
        ->check(CLI::PositiveNumber);
    render_
        ->add_option("--dpi", dpi_,
                     "Pixels per inch (default 100; 8 inch wide pictures, as tall as the domain needs)")
        ->check(CLI::Range(20, 1000));
    render_->add_option("--info", info_, "Also write where axes and colour bar lie in the picture (JSON)");
    render_
        ->add_option("--view", view_, "3D runs: section (z = const, default) or top (the surface from above)")
        ->check(CLI::IsMember({"section", "top"}));
    render_->add_option("--section-z", section_z_,
                        "3D section: z of the plane [m] (default: the middle of the material)");
    render_
        ->add_option("--slab", slab_,
                     "3D section: thickness of the slab of points drawn [m] (default: one voxel)")
        ->check(CLI::PositiveNumber);
    render_
        ->add_option("--map", map_,
                     "3D runs, with --view top: the hazard map NAME (maps/NAME.asc) over a hillshade of the "
                     "terrain, with a scale bar and the runout outline")
        ->check(CLI::IsMember({"deposit_thickness", "height_change", "max_speed", "max_displacement",
                               "arrival_time", "terrain"}));

    report_ = app.add_subcommand("report", "Write a self-contained HTML report of a run");
    report_->add_option("outdir", outdir_, "Output folder of `skred run`")
        ->required()
        ->check(CLI::ExistingDirectory);
    report_->add_option("-o,--output", output_, "HTML file (default OUTDIR/report.html)");
    report_->add_option("--field", field_, "Field of the frame pictures (default: displacement magnitude)");
  }

  bool chosen() const { return render_->parsed() || report_->parsed(); }

  // Replaces the process by the Python post-processing; returns an exit status on failure.
  int run() const { return exec_post(args()); }

 private:
  std::vector<std::string> args() const {
    std::vector<std::string> a = {render_->parsed() ? "render" : "report", outdir_};
    auto opt = [&a](const char* flag, const std::string& v) {
      if (!v.empty()) a.insert(a.end(), {flag, v});
    };
    auto num = [](double v) { return fmt::format("{}", v); };
    opt("--output", output_);
    opt("--field", field_);
    if (report_->parsed()) return a;
    if (render_->count("--step")) opt("--step", std::to_string(step_));
    if (all_) a.push_back("--all");
    if (series_) a.push_back("--series");
    if (arrows_) a.push_back("--arrows");
    if (crosses_) a.push_back("--crosses");
    if (slip_circle_) a.push_back("--slip-circle");
    if (stripes_) a.push_back("--stripes");
    if (checker_) a.push_back("--checkerboard");
    if (render_->count("--pattern-width")) opt("--pattern-width", num(pattern_width_));
    if (render_->count("--pattern-angle")) opt("--pattern-angle", num(pattern_angle_));
    if (range_.size() == 2) a.insert(a.end(), {"--range", num(range_[0]), num(range_[1])});
    opt("--cmap", cmap_);
    if (render_->count("--sample")) opt("--sample", std::to_string(sample_));
    if (render_->count("--fps")) opt("--fps", num(fps_));
    if (render_->count("--dpi")) opt("--dpi", std::to_string(dpi_));
    opt("--info", info_);
    opt("--view", view_);
    if (render_->count("--section-z")) opt("--section-z", num(section_z_));
    if (render_->count("--slab")) opt("--slab", num(slab_));
    opt("--map", map_);
    return a;
  }

  CLI::App* render_ = nullptr;
  CLI::App* report_ = nullptr;
  std::string outdir_, field_, output_, cmap_, info_, view_, map_;
  int step_ = -1, sample_ = 4, dpi_ = 100;
  bool all_ = false, series_ = false, arrows_ = false, crosses_ = false, slip_circle_ = false,
       stripes_ = false, checker_ = false;
  double pattern_width_ = 0.0, pattern_angle_ = 0.0, fps_ = 8.0, section_z_ = 0.0, slab_ = 0.0;
  std::vector<double> range_;
};

}  // namespace skred
