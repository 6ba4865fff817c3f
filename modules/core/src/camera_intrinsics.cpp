#include "pf2/core/camera_intrinsics.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "pf2/core/text_lines.h"

namespace pf2 {

namespace {
CameraIntrinsics make(double fx, double fy, double cx, double cy) {
  CameraIntrinsics k;
  k.fx = fx;
  k.fy = fy;
  k.cx = cx;
  k.cy = cy;
  k.width = 640;
  k.height = 480;
  return k;
}
}  // namespace

CameraIntrinsics CameraIntrinsics::tumFreiburg1() { return make(517.3, 516.5, 318.6, 255.3); }
CameraIntrinsics CameraIntrinsics::tumFreiburg2() { return make(520.9, 521.0, 325.1, 249.7); }
CameraIntrinsics CameraIntrinsics::tumFreiburg3() { return make(535.4, 539.2, 320.1, 247.6); }
CameraIntrinsics CameraIntrinsics::bonnDynamic() {
  return make(542.822841, 542.576870, 315.593520, 237.756098);
}

CameraIntrinsics CameraIntrinsics::preset(const std::string& name) {
  if (name == "fr1") return tumFreiburg1();
  if (name == "fr2") return tumFreiburg2();
  if (name == "fr3") return tumFreiburg3();
  if (name == "bonn") return bonnDynamic();
  throw Error("unknown camera preset '" + name + "' (expected fr1, fr2, fr3 or bonn)");
}

CameraIntrinsics CameraIntrinsics::load(const std::string& path) {
  std::map<std::string, std::pair<double, int>> values;  // key -> (value, line)
  forEachDataLine(path, "calibration file", [&](std::string line, int line_number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::string key;
    if (!(fields >> key)) return;  // only a trailing comment
    double value = 0.0;
    std::string extra;
    if (!(fields >> value) || (fields >> extra) || !std::isfinite(value)) {
      throw fileError(path, line_number, "expected 'key value' with a finite number, got '" + line + "'");
    }
    if (key != "fx" && key != "fy" && key != "cx" && key != "cy" && key != "width" && key != "height") {
      throw fileError(path, line_number, "unknown key '" + key + "' (expected fx, fy, cx, cy, width, height)");
    }
    if (values.count(key)) {
      throw fileError(path, line_number,
                      "key '" + key + "' set twice (first on line " + std::to_string(values[key].second) + ")");
    }
    values[key] = {value, line_number};
  });
  for (const char* key : {"fx", "fy", "cx", "cy", "width", "height"}) {
    if (!values.count(key)) throw fileError(path, std::string("missing key '") + key + "'");
  }
  // Ranges a real camera lies in: focal lengths from a fish-eye's to a telephoto's, the principal
  // point inside the image, sizes up to 8K.
  const auto check = [&](const char* key, double lo, double hi) {
    const auto& [value, line] = values[key];
    if (!(value >= lo && value <= hi)) {
      char range[96];
      std::snprintf(range, sizeof(range), "%s = %g: outside its range [%g, %g]", key, value, lo, hi);
      throw fileError(path, line, range);
    }
    return value;
  };
  CameraIntrinsics k;
  k.width = static_cast<int>(check("width", 8, 16384));
  k.height = static_cast<int>(check("height", 8, 16384));
  if (values["width"].first != k.width || values["height"].first != k.height) {
    throw fileError(path, values["width"].second, "width and height must be whole numbers of pixels");
  }
  k.fx = check("fx", 10, 1e5);
  k.fy = check("fy", 10, 1e5);
  k.cx = check("cx", 0, k.width - 1);
  k.cy = check("cy", 0, k.height - 1);
  return k;
}

void CameraIntrinsics::save(const std::string& path) const {
  writeFileAtomically(path, [this](std::ostream& out) {
    out.precision(10);
    out << "# PoseFusion2 camera calibration (pinhole, pixels)\n"
        << "fx " << fx << "\nfy " << fy << "\ncx " << cx << "\ncy " << cy << "\nwidth " << width
        << "\nheight " << height << "\n";
  });
}

CameraIntrinsics CameraIntrinsics::scaled(double factor) const {
  CameraIntrinsics k = *this;
  k.fx *= factor;
  k.fy *= factor;
  // Pixel centres: continuous coordinate c maps to (c + 0.5) * f - 0.5.
  k.cx = (cx + 0.5) * factor - 0.5;
  k.cy = (cy + 0.5) * factor - 0.5;
  k.width = static_cast<int>(width * factor + 0.5);
  k.height = static_cast<int>(height * factor + 0.5);
  return k;
}

}  // namespace pf2
