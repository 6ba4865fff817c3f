#include "pf2/humans/body_tracks_io.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"

namespace pf2 {

namespace {

// Numbers as "a,b,c" with 6 decimals (micrometres, microradians).
void writeNumbers(std::ostream& out, const double* values, int count) {
  char text[40];
  for (int i = 0; i < count; ++i) {
    const int n = std::snprintf(text, sizeof(text), "%s%.6f", i ? "," : "", values[i]);
    out.write(text, n);
  }
}

void writeFrame(std::ostream& out, const BodyTrackFrame& f) {
  char stamp[40];
  std::snprintf(stamp, sizeof(stamp), "%.6f", f.timestamp);
  out << "{\"timestamp\":" << stamp << ",\"T_w_h\":[";
  const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> T = f.T_w_h.matrix();
  writeNumbers(out, T.data(), 16);
  out << "],\"pose\":[";
  for (int j = 0; j < kBodyJointCount; ++j) {
    if (j) out << ',';
    writeNumbers(out, f.body_w.pose[j].data(), 3);
  }
  out << "],\"shape\":[";
  writeNumbers(out, f.body_w.shape.data(), static_cast<int>(f.body_w.shape.size()));
  out << "],\"translation\":[";
  writeNumbers(out, f.body_w.translation.data(), 3);
  out << "],\"joints_w\":[";
  for (int j = 0; j < kBodyJointCount; ++j) {
    out << (j ? ",[" : "[");
    writeNumbers(out, f.joints_w[j].data(), 3);
    out << ']';
  }
  out << "],\"pelvis_w\":[";
  writeNumbers(out, f.pelvis_w.data(), 3);
  out << "],\"fitted\":" << (f.fitted ? "true" : "false") << '}';
}

double finiteNumber(const nlohmann::json& value, const std::string& key) {
  if (!value.is_number() || !std::isfinite(value.get<double>())) {
    throw Error("\"" + key + "\" holds a value that is not a finite number");
  }
  return value.get<double>();
}

// A list of `count` finite numbers; throws naming the key.
std::vector<double> numberList(const nlohmann::json& list, const std::string& key, size_t count) {
  if (!list.is_array() || list.size() != count) {
    throw Error("\"" + key + "\" must be a list of " + std::to_string(count) + " numbers");
  }
  std::vector<double> values;
  for (const nlohmann::json& v : list) values.push_back(finiteNumber(v, key));
  return values;
}

std::vector<double> numbers(const nlohmann::json& object, const char* key, size_t count) {
  if (!object.contains(key)) throw Error(std::string("no \"") + key + "\"");
  return numberList(object[key], key, count);
}

BodyTrackFrame readFrame(const nlohmann::json& j) {
  BodyTrackFrame f;
  if (!j.is_object() || !j.contains("timestamp")) throw Error("no \"timestamp\"");
  f.timestamp = finiteNumber(j["timestamp"], "timestamp");
  const std::vector<double> T = numbers(j, "T_w_h", 16);
  f.T_w_h.matrix() = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(T.data());
  const std::vector<double> pose = numbers(j, "pose", 3 * kBodyJointCount);
  for (int k = 0; k < kBodyJointCount; ++k) f.body_w.pose[k] = Eigen::Vector3d(&pose[3 * k]);
  if (!j.contains("shape") || !j["shape"].is_array()) throw Error("\"shape\" must be a list of numbers");
  const std::vector<double> shape = numbers(j, "shape", j["shape"].size());
  f.body_w.shape = Eigen::Map<const Eigen::VectorXd>(shape.data(), static_cast<Eigen::Index>(shape.size()));
  const std::vector<double> translation = numbers(j, "translation", 3);
  f.body_w.translation = Eigen::Vector3d(translation[0], translation[1], translation[2]);
  if (!j.contains("joints_w") || !j["joints_w"].is_array() || j["joints_w"].size() != kBodyJointCount) {
    throw Error("\"joints_w\" must be a list of 24 [x, y, z]");
  }
  for (int k = 0; k < kBodyJointCount; ++k) {
    const std::vector<double> p = numberList(j["joints_w"][k], "joints_w", 3);
    f.joints_w[k] = Eigen::Vector3d(p[0], p[1], p[2]);
  }
  const std::vector<double> pelvis = numbers(j, "pelvis_w", 3);
  f.pelvis_w = Eigen::Vector3d(pelvis[0], pelvis[1], pelvis[2]);
  if (!j.contains("fitted") || !j["fitted"].is_boolean()) throw Error("\"fitted\" must be true or false");
  f.fitted = j["fitted"].get<bool>();
  return f;
}

}  // namespace

void writeBodyTracksJson(const std::string& path, const std::vector<BodyTrack>& tracks) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "{\"tracks\":[";
    for (size_t t = 0; t < tracks.size(); ++t) {
      out << (t ? ",\n" : "\n") << "{\"id\":" << tracks[t].id << ",\"frames\":[";
      for (size_t i = 0; i < tracks[t].frames.size(); ++i) {
        out << (i ? ",\n" : "\n");
        writeFrame(out, tracks[t].frames[i]);
      }
      out << "]}";
    }
    out << "\n]}\n";
  });
}

std::vector<BodyTrack> readBodyTracksJson(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) throw fileError(path, "is a folder, not humans.json");
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open humans.json");
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    throw fileError(path, "not a JSON document");
  }
  if (!root.is_object() || !root.contains("tracks") || !root["tracks"].is_array()) {
    throw fileError(path, "expected {\"tracks\": [...]}");
  }
  std::vector<BodyTrack> tracks;
  for (const nlohmann::json& t : root["tracks"]) {
    BodyTrack track;
    if (!t.is_object() || !t.contains("id") || !t["id"].is_number_integer() || !t.contains("frames") ||
        !t["frames"].is_array()) {
      throw fileError(path, "track " + std::to_string(tracks.size() + 1) + ": expected {\"id\": N, \"frames\": [...]}");
    }
    track.id = t["id"].get<int>();
    for (const nlohmann::json& f : t["frames"]) {
      try {
        track.frames.push_back(readFrame(f));
      } catch (const Error& e) {
        throw fileError(path, "track " + std::to_string(track.id) + ", frame " +
                                  std::to_string(track.frames.size() + 1) + ": " + e.what());
      }
    }
    if (!track.frames.empty()) track.shape = track.frames.front().body_w.shape;
    tracks.push_back(std::move(track));
  }
  return tracks;
}

}  // namespace pf2
