// pf2_view: an interactive 3D view of a pf2_slam output folder (map mesh, camera trajectory,
// people's tracks) through PCL's visualiser. Everything is read and checked before a window opens,
// so bad input ends with one error line and never with a half-drawn window.
#include <pcl/PolygonMesh.h>
#include <pcl/console/print.h>
#include <pcl/point_types.h>
#include <pcl/visualization/pcl_visualizer.h>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkImageData.h>
#include <vtkPoints.h>
#include <vtkRendererCollection.h>
#include <vtkRenderer.h>
#include <vtkPolyData.h>
#include <vtkPolyLine.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkSmartPointer.h>
#include <vtkWindowToImageFilter.h>

#include <X11/Xlib.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "pf2/core/app_settings.h"
#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/core/settings.h"
#include "pf2/humans/body_tracks_io.h"
#include "pf2/io/image_file.h"
#include "pf2/humans/human_track.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/surface/triangle_mesh.h"

namespace {

namespace fs = std::filesystem;

const char* kUsage =
    "Usage: pf2_view RUN_DIR [options]\n"
    "Shows a pf2_slam output folder in 3D: the static map (map.ply, vertex colours), the camera\n"
    "trajectory (trajectory.txt, white polyline, a camera frustum every N poses, the first one green)\n"
    "and each person's track (humans.txt, one colour per id, the id written at its last position),\n"
    "with their bodies (humans.json, when the run fitted them) in the same colours.\n"
    "trajectory.txt is required; a missing map.ply or humans.txt is skipped with a note.\n"
    "\n"
    "Options:\n"
    "  --no-map            do not load or show map.ply\n"
    "  --screenshot FILE   render one frame, save it as PNG and exit (needs an X display;\n"
    "                      under a headless shell: xvfb-run -a pf2_view ...)\n"
    "  --size WxH          window size in pixels (default 1280x800)\n"
    "  --camera-every N    draw a camera frustum every N poses (default 30; 0: none)\n"
    "  -h, --help          this text\n"
    "  --body-time S       show the bodies at S seconds from their first frame (default: each\n"
    "                      person's last fitted body)\n"
    "--no-map, --size, --camera-every and --body-time are the settings view.map, view.size,\n"
    "view.camera_every and view.body_time:\n";
const char* kKeys =
    "\n"
    "Keys (PCL's defaults): r reset the view to fit everything, left drag rotate, middle drag or\n"
    "shift+left drag pan, wheel zoom, f fly to the point under the mouse, w wireframe, s surface,\n"
    "g scale grid, j save a screenshot, o perspective/parallel projection, c print the camera,\n"
    "+/- point size, h print all keys to the terminal, q quit. Bodies: , and . step one frame back\n"
    "and forward, < and > 30 frames (the first step goes to the last frame).\n"
    "Exit status: 0 on success, 1 on bad input (the error line names the file).\n";

// What a run folder holds, read and validated before any window exists.
struct RunData {
  pf2::Trajectory trajectory;
  pf2::TriangleMesh map;
  std::vector<pf2::HumanTrack> people;
  std::vector<pf2::BodyTrack> bodies;  // humans.json, when the run fitted bodies
  bool has_map = false;
};

RunData loadRun(const fs::path& dir, bool with_map) {
  if (!fs::is_directory(dir)) throw pf2::fileError(dir.string(), "no such folder");
  RunData run;
  const fs::path trajectory_path = dir / "trajectory.txt";
  if (!fs::exists(trajectory_path)) {
    throw pf2::fileError(trajectory_path.string(), "no such file (not a pf2_slam output folder?)");
  }
  run.trajectory = pf2::readTrajectory(trajectory_path.string());
  if (run.trajectory.empty()) throw pf2::fileError(trajectory_path.string(), "no poses in file");

  const fs::path map_path = dir / "map.ply";
  if (!with_map) {
    std::printf("note: --no-map, %s not loaded\n", map_path.string().c_str());
  } else if (!fs::exists(map_path)) {
    std::printf("note: %s not found, no map shown\n", map_path.string().c_str());
  } else {
    run.map = pf2::loadMeshPly(map_path.string());
    run.has_map = !run.map.empty();
    if (!run.has_map) std::printf("note: %s has no triangles, no map shown\n", map_path.string().c_str());
  }

  const fs::path humans_path = dir / "humans.txt";
  if (fs::exists(humans_path)) {
    run.people = pf2::readHumanTracks(humans_path.string());
  } else {
    std::printf("note: %s not found, no people shown\n", humans_path.string().c_str());
  }
  const fs::path bodies_path = dir / "humans.json";
  if (fs::exists(bodies_path)) run.bodies = pf2::readBodyTracksJson(bodies_path.string());
  return run;
}

// "WxH" with both sides in [64, 8192].
// pf2_view's settings (view.*), declared once: --config, --set and the options read them.
struct ViewSettings {
  bool with_map = true;
  std::array<int, 2> size{1280, 800};
  int camera_every = 30;
  double body_time = -1;  // s from the first body frame; < 0: each person's last fitted body
};

pf2::Settings declareViewSettings(ViewSettings* v) {
  pf2::Settings s;
  s.boolean("view.map", &v->with_map, "load and show map.ply");
  s.custom(
      "view.size",
      [v](const std::string& text) {
        int w = 0, h = 0;
        char tail = 0;
        if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 64 || h < 64 || w > 8192 ||
            h > 8192) {
          throw pf2::Error("expected WxH with sides 64..8192");
        }
        v->size = {w, h};
      },
      [v] { return std::to_string(v->size[0]) + "x" + std::to_string(v->size[1]); }, "WxH, sides 64..8192",
      "window (or screenshot) size in pixels");
  s.integer("view.camera_every", &v->camera_every, 0, 1000000, "poses", "a camera frustum every this many poses (0: none)");
  s.number("view.body_time", &v->body_time, -1.0, 1e7, "seconds",
           "show the bodies of humans.json at this time from their first frame (-1: each person's last fitted body)");
  return s;
}

// Axis-aligned bounds of the points shown, for the view's centre and the size of glyphs.
struct Bounds {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  explicit Bounds(const std::vector<Eigen::Vector3d>& points) {
    for (const Eigen::Vector3d& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  Eigen::Vector3d centre() const { return 0.5 * (lo + hi); }
  // Half the diagonal, at least 0.5 m so that a single pose still gets a sensible view.
  double radius() const { return std::max(0.5, 0.5 * (hi - lo).norm()); }
};

// Camera centres, track points and (a sample of) the map's vertices: what the view must frame.
std::vector<Eigen::Vector3d> pointsToFrame(const RunData& run) {
  std::vector<Eigen::Vector3d> points;
  for (const pf2::StampedPose& pose : run.trajectory) points.push_back(pose.T_w_c.translation());
  for (const pf2::HumanTrack& track : run.people) {
    for (const pf2::HumanTrackPoint& p : track.points) points.push_back(p.p_w);
  }
  if (run.has_map) {
    // Every vertex of a large map is not needed to frame it; about 100k spread over it are.
    const std::size_t stride = 1 + run.map.vertices.size() / 100000;
    for (std::size_t i = 0; i < run.map.vertices.size(); i += stride) {
      points.push_back(run.map.vertices[i].cast<double>());
    }
  }
  return points;
}

// A polyline through points, or separate segments (pairs of points) when `segments` is set.
vtkSmartPointer<vtkPolyData> makeLines(const std::vector<Eigen::Vector3d>& points, bool segments) {
  auto vtk_points = vtkSmartPointer<vtkPoints>::New();
  for (const Eigen::Vector3d& p : points) vtk_points->InsertNextPoint(p.x(), p.y(), p.z());
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  if (segments) {
    for (vtkIdType i = 0; i + 1 < static_cast<vtkIdType>(points.size()); i += 2) {
      const vtkIdType ids[2] = {i, i + 1};
      cells->InsertNextCell(2, ids);
    }
  } else {
    auto line = vtkSmartPointer<vtkPolyLine>::New();
    line->GetPointIds()->SetNumberOfIds(static_cast<vtkIdType>(points.size()));
    for (vtkIdType i = 0; i < static_cast<vtkIdType>(points.size()); ++i) line->GetPointIds()->SetId(i, i);
    cells->InsertNextCell(line);
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  data->SetPoints(vtk_points);
  data->SetLines(cells);
  return data;
}

void addLines(pcl::visualization::PCLVisualizer& viewer, const std::vector<Eigen::Vector3d>& points,
              bool segments, const std::array<double, 3>& rgb, double width, const std::string& id) {
  viewer.addModelFromPolyData(makeLines(points, segments), id);
  viewer.setShapeRenderingProperties(pcl::visualization::PCL_VISUALIZER_COLOR, rgb[0], rgb[1], rgb[2], id);
  viewer.setShapeRenderingProperties(pcl::visualization::PCL_VISUALIZER_LINE_WIDTH, width, id);
  // Unlit, so that a line has exactly its colour from every side (and matches its id label).
  vtkActor* actor = vtkActor::SafeDownCast(viewer.getShapeActorMap()->at(id));
  if (actor != nullptr) actor->GetProperty()->LightingOff();
}

// Segments of a pinhole frustum (apex at the camera centre, 4:3 image, camera x right, y down,
// z forward) of the given depth, appended to `out`.
void appendFrustum(const Eigen::Isometry3d& T_w_c, double depth, std::vector<Eigen::Vector3d>* out) {
  const Eigen::Vector3d apex = T_w_c.translation();
  const double hx = 0.5 * depth, hy = 0.375 * depth;
  const std::array<Eigen::Vector3d, 4> corners = {
      T_w_c * Eigen::Vector3d(-hx, -hy, depth), T_w_c * Eigen::Vector3d(hx, -hy, depth),
      T_w_c * Eigen::Vector3d(hx, hy, depth), T_w_c * Eigen::Vector3d(-hx, hy, depth)};
  for (int i = 0; i < 4; ++i) {
    out->insert(out->end(), {apex, corners[i], corners[i], corners[(i + 1) % 4]});
  }
}

// Refuses to go on without a reachable X display: VTK's X render window aborts the process
// when it cannot open one. The connection is kept open until the viewer is gone, because an X
// server (Xvfb too) resets when its last client leaves and would refuse VTK's connection meanwhile.
struct DisplayCloser {
  void operator()(Display* display) const { XCloseDisplay(display); }
};
std::unique_ptr<Display, DisplayCloser> openDisplay() {
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || *name == '\0') {
    throw pf2::Error("no X display (DISPLAY is not set); run under a desktop or xvfb-run -a");
  }
  std::unique_ptr<Display, DisplayCloser> display(XOpenDisplay(name));
  if (!display) throw pf2::Error(std::string("cannot open X display '") + name + "'");
  return display;
}

// Renders one frame and writes it as PNG. PCLVisualizer::saveScreenshot needs the interactor,
// which a one-shot render does not create.
void saveScreenshot(vtkRenderWindow* window, const std::string& path) {
  window->Render();
  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  // VTK's rows run bottom to top, RGB; written through our own writer (one error line on a full
  // disk, never half a file).
  vtkImageData* image = grab->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  const cv::Mat rgb(dims[1], dims[0], CV_8UC3, image->GetScalarPointer());
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  cv::flip(bgr, bgr, 0);
  pf2::writeImageFile(path, bgr);
}

// The people's bodies (humans.json) at one moment: each person's last fitted body (the view
// scene.ply gives), or every body of one frame, stepped through time with keys.
class BodyPlayer {
 public:
  BodyPlayer(const std::vector<pf2::BodyTrack>& tracks, const pf2::BodyModel* model) : tracks_(tracks), model_(model) {
    for (const pf2::BodyTrack& track : tracks_) {
      for (const pf2::BodyTrackFrame& f : track.frames) times_.push_back(f.timestamp);
    }
    std::sort(times_.begin(), times_.end());
    times_.erase(std::unique(times_.begin(), times_.end()), times_.end());
  }

  bool empty() const { return times_.empty(); }

  void showLastFitted(pcl::visualization::PCLVisualizer& viewer) {
    clear(viewer);
    for (const pf2::BodyTrack& track : tracks_) {
      if (track.frames.empty()) continue;
      auto last = std::find_if(track.frames.rbegin(), track.frames.rend(),
                               [](const pf2::BodyTrackFrame& f) { return f.fitted; });
      add(viewer, track.id, last != track.frames.rend() ? *last : track.frames.back());
    }
    status(viewer, "bodies: each person's last fitted body   , . step a frame   < > 30 frames");
  }

  // The bodies of frame `index` of the run's body frames (clamped to the first and last).
  void showFrame(pcl::visualization::PCLVisualizer& viewer, long index) {
    current_ = std::clamp<long>(index, 0, static_cast<long>(times_.size()) - 1);
    const double t = times_[current_];
    clear(viewer);
    for (const pf2::BodyTrack& track : tracks_) {
      const auto f = std::find_if(track.frames.begin(), track.frames.end(),
                                  [t](const pf2::BodyTrackFrame& frame) { return std::abs(frame.timestamp - t) < 1e-7; });
      if (f != track.frames.end()) add(viewer, track.id, *f);
    }
    char text[160];
    std::snprintf(text, sizeof(text), "bodies at t = %.2f s (frame %ld of %zu)   , . step a frame   < > 30 frames",
                  t - times_.front(), current_ + 1, times_.size());
    status(viewer, text);
  }

  // The bodies of the frame nearest `seconds` after the first body frame.
  void showAt(pcl::visualization::PCLVisualizer& viewer, double seconds) {
    const auto it = std::lower_bound(times_.begin(), times_.end(), times_.front() + seconds);
    showFrame(viewer, static_cast<long>(it - times_.begin()));
  }

  // From the last fitted bodies, stepping starts at the end.
  void step(pcl::visualization::PCLVisualizer& viewer, long frames) {
    showFrame(viewer, current_ < 0 ? static_cast<long>(times_.size()) - 1 : current_ + frames);
  }

 private:
  void add(pcl::visualization::PCLVisualizer& viewer, int id, const pf2::BodyTrackFrame& frame) {
    pcl::PolygonMesh mesh;
    pf2::toPolygonMesh(model_->evaluate(frame.body_w), &mesh);
    const std::string name = "body_" + std::to_string(id);
    viewer.addPolygonMesh(mesh, name);
    const std::array<double, 3> rgb = pf2::personColour(id);
    viewer.setPointCloudRenderingProperties(pcl::visualization::PCL_VISUALIZER_COLOR, rgb[0], rgb[1], rgb[2], name);
    shown_.push_back(name);
  }
  void clear(pcl::visualization::PCLVisualizer& viewer) {
    for (const std::string& name : shown_) viewer.removePolygonMesh(name);
    shown_.clear();
  }
  void status(pcl::visualization::PCLVisualizer& viewer, const std::string& text) {
    if (!viewer.updateText(text, 10, 50, 12, 0.9, 0.9, 0.9, "bodies")) {
      viewer.addText(text, 10, 50, 12, 0.9, 0.9, 0.9, "bodies");
    }
  }

  const std::vector<pf2::BodyTrack>& tracks_;
  const pf2::BodyModel* model_;
  std::vector<double> times_;  // every body frame's timestamp, sorted, once each
  long current_ = -1;          // index into times_; -1 = the last fitted bodies
  std::vector<std::string> shown_;
};

// The run folder's own name for the legend ("view_run" for "out/view_run/" or ".").
std::string runName(const fs::path& dir) {
  fs::path path = fs::absolute(dir).lexically_normal();
  if (path.filename().empty()) path = path.parent_path();
  return path.filename().string();
}

// Height of the legend band at the bottom of the window, pixels.
constexpr int kLegendPixels = 70;

// Distance from `centre` along `back` at which every point lies within tan_h and tan_v of the
// view axis: a tighter framing than VTK's ResetCamera, which fits the bounding sphere.
double fitDistance(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& centre,
                   const Eigen::Vector3d& back, const Eigen::Vector3d& up, double tan_h, double tan_v) {
  const Eigen::Vector3d right = up.cross(back).normalized(), true_up = back.cross(right);
  double distance = 1e-3;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d d = p - centre;
    const double toward = d.dot(back);  // how much nearer to the camera than the centre
    distance = std::max({distance, toward + std::abs(d.dot(right)) / tan_h, toward + std::abs(d.dot(true_up)) / tan_v});
  }
  return distance;
}

void buildScene(pcl::visualization::PCLVisualizer& viewer, const RunData& run, int camera_every,
                const std::string& name, int width, int height) {
  std::vector<Eigen::Vector3d> shown = pointsToFrame(run);
  const Bounds bounds(shown);
  const double radius = bounds.radius();
  viewer.setBackgroundColor(0.12, 0.12, 0.14);
  viewer.setShowFPS(false);

  if (run.has_map) {
    pcl::PolygonMesh mesh;
    pf2::toPolygonMesh(run.map, &mesh);
    viewer.addPolygonMesh(mesh, "map");
  }

  std::vector<Eigen::Vector3d> centres;
  for (const pf2::StampedPose& pose : run.trajectory) centres.push_back(pose.T_w_c.translation());
  if (centres.size() >= 2) addLines(viewer, centres, false, {1.0, 1.0, 1.0}, 2.0, "trajectory");
  // Frusta sized to the scene, so that they stay visible on a room and on a corridor alike.
  const double frustum_depth = 0.06 * radius;
  std::vector<Eigen::Vector3d> frusta;
  if (camera_every > 0) {
    for (std::size_t i = camera_every; i < run.trajectory.size(); i += camera_every) {
      appendFrustum(run.trajectory[i].T_w_c, frustum_depth, &frusta);
    }
    if (!frusta.empty()) addLines(viewer, frusta, true, {0.85, 0.85, 0.85}, 1.0, "frusta");
  }
  std::vector<Eigen::Vector3d> first;
  appendFrustum(run.trajectory.front().T_w_c, frustum_depth, &first);
  addLines(viewer, first, true, {0.2, 1.0, 0.3}, 2.0, "first_camera");

  for (const pf2::HumanTrack& track : run.people) {
    if (track.points.empty()) continue;
    const std::string id = "person_" + std::to_string(track.id);
    const std::array<double, 3> rgb = pf2::personColour(track.id);
    std::vector<Eigen::Vector3d> points;
    for (const pf2::HumanTrackPoint& p : track.points) points.push_back(p.p_w);
    if (points.size() >= 2) addLines(viewer, points, false, rgb, 3.0, id);
    pcl::PointXYZ label;
    label.getVector3fMap() = points.back().cast<float>();
    viewer.addText3D(std::to_string(track.id), label, 0.05 * radius, rgb[0], rgb[1], rgb[2], id + "_label");
  }

  const std::string legend =
      name + "   " + std::to_string(run.trajectory.size()) + " poses (white, first green)   " +
      (run.has_map ? std::to_string(run.map.triangles.size()) + " map triangles" : std::string("no map")) +
      "   " + std::to_string(run.people.size()) + " people (coloured, id at last position)";
  viewer.addText(legend, 10, 30, 14, 0.9, 0.9, 0.9, "legend");
  viewer.addText("r reset view   w/s wireframe/surface   j screenshot   h keys   q quit", 10, 10, 12, 0.7, 0.7,
                 0.7, "help");

  // Start behind and above the first camera, looking at the middle of everything, with the
  // first camera's "up" (its -y) as up: a view of the run as the camera first saw it.
  const Eigen::Isometry3d& T0 = run.trajectory.front().T_w_c;
  const Eigen::Vector3d up = -T0.linear().col(1);
  const Eigen::Vector3d back = (-1.6 * T0.linear().col(2) + 1.1 * up).normalized();
  const Eigen::Vector3d centre = bounds.centre();
  shown.insert(shown.end(), frusta.begin(), frusta.end());
  shown.insert(shown.end(), first.begin(), first.end());
  // VTK's default 30 degree vertical view angle, a 10 % margin, and the bottom kLegendPixels
  // kept for the legend: the view is fitted to the rest and shifted up into it.
  const double usable = static_cast<double>(height - kLegendPixels) / height;
  const double tan_v = 0.9 * std::tan(0.5 * 30.0 * M_PI / 180.0);
  const double distance =
      fitDistance(shown, centre, back, up, tan_v * static_cast<double>(width) / height, tan_v * usable);
  const Eigen::Vector3d eye = centre + distance * back;
  viewer.setCameraPosition(eye.x(), eye.y(), eye.z(), centre.x(), centre.y(), centre.z(), up.x(), up.y(), up.z());
  viewer.getRendererCollection()->GetFirstRenderer()->GetActiveCamera()->SetWindowCenter(0.0, usable - 1.0);
  viewer.setCameraClipDistances(0.01 * distance, distance + 4.0 * radius);
}

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  ViewSettings view;
  pf2::Settings settings = declareViewSettings(&view);
  if (pf2::answeredHelpOrSettings(&cli, std::string(kUsage) + pf2::kSettingsUsage + kKeys, settings)) return 0;
  pf2::readCommandLineSettings(&cli, &settings,
                               {{"--no-map", "view.map", "false"},
                                {"--size", "view.size"},
                                {"--camera-every", "view.camera_every"},
                                {"--body-time", "view.body_time"}});
  const bool with_map = view.with_map;
  const std::array<int, 2>& size = view.size;
  const int camera_every = view.camera_every;
  const auto screenshot = cli.value("--screenshot");
  const auto args = cli.positionals();
  if (args.size() != 1) {
    throw pf2::Error("expected one RUN_DIR, got " + std::to_string(args.size()) + " argument(s) (see -h)");
  }
  if (screenshot && fs::path(*screenshot).extension() != ".png") {
    throw pf2::fileError(*screenshot, "--screenshot writes PNG only (name it .png)");
  }
  // Checked now rather than after VTK's writer has printed its own complaints.
  if (screenshot && !fs::is_directory(fs::absolute(*screenshot).parent_path())) {
    throw pf2::fileError(*screenshot, "no such folder for the screenshot");
  }

  // PCL's readers print their own diagnostics; ours already name the file in one line.
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  const fs::path dir(args[0]);
  const RunData data = loadRun(dir, with_map);
  const auto display = openDisplay();

  pcl::visualization::PCLVisualizer viewer("pf2_view " + dir.string(), !screenshot.has_value());
  // A screenshot is rendered into an off-screen buffer: no window flashes up on a desktop.
  if (screenshot) viewer.getRenderWindow()->SetOffScreenRendering(1);
  viewer.setSize(size[0], size[1]);
  buildScene(viewer, data, camera_every, runName(dir), size[0], size[1]);
  // The bodies (humans.json) at the chosen moment; keys step through time.
  std::unique_ptr<pf2::BodyModel> body_model;
  std::unique_ptr<BodyPlayer> bodies;
  if (!data.bodies.empty()) {
    body_model = std::make_unique<pf2::BodyModel>(pf2::BodyModel::loadDefault());
    bodies = std::make_unique<BodyPlayer>(data.bodies, body_model.get());
    if (view.body_time < 0) {
      bodies->showLastFitted(viewer);
    } else {
      bodies->showAt(viewer, view.body_time);
    }
    viewer.registerKeyboardCallback([&viewer, &bodies](const pcl::visualization::KeyboardEvent& event) {
      if (!event.keyDown()) return;
      const std::string key = event.getKeySym();
      const long step = key == "period" ? 1 : key == "comma" ? -1 : key == "greater" ? 30 : key == "less" ? -30 : 0;
      if (step != 0) bodies->step(viewer, step);
    });
  }
  if (screenshot) {
    saveScreenshot(viewer.getRenderWindow(), *screenshot);
    std::printf("wrote %s (%dx%d)\n", screenshot->c_str(), size[0], size[1]);
    return 0;
  }
  viewer.spin();
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_view", run, argc, argv); }
