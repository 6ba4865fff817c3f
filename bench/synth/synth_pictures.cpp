// Writes the pictures of docs/synth.md: a synthetic frame (colour, depth, person mask) and the body
// model alone (rest pose, walking, two shapes), drawn with the synthetic rasteriser.
//   pf2_synth_pictures OUT_DIR
#include <cmath>
#include <iostream>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/synth/people.h"
#include "pf2/synth/synthetic_sequence.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

cv::Mat colourDepth(const cv::Mat& depth) {
  cv::Mat scaled, coloured;
  depth.convertTo(scaled, CV_8U, 255.0 / 4.5);
  cv::applyColorMap(scaled, coloured, cv::COLORMAP_TURBO);
  coloured.setTo(cv::Scalar(0, 0, 0), depth == 0);
  return coloured;
}

cv::Mat colourLabels(const cv::Mat& labels) {
  static const cv::Vec3b kColours[] = {{60, 60, 60}, {60, 80, 230}, {80, 200, 60}, {230, 140, 40},
                                       {40, 200, 230}, {200, 60, 200}};
  cv::Mat out(labels.size(), CV_8UC3);
  for (int v = 0; v < labels.rows; ++v) {
    for (int u = 0; u < labels.cols; ++u) out.at<cv::Vec3b>(v, u) = kColours[std::min<int>(labels.at<std::uint16_t>(v, u), 5)];
  }
  return out;
}

// The body alone, standing on the origin facing the camera, lit from the front left.
// `azimuth` turns the camera around the body (0 = in front, slightly from its left).
cv::Mat renderBody(const pf2::BodyModel& model, pf2::BodyParameters parameters, const cv::Vec3f& colour,
                   double azimuth = 0.0) {
  // Body frame (y up, facing +z) to a z-up world, facing -y (towards the camera).
  const Eigen::Matrix3d R_w_b = Eigen::AngleAxisd(kPi / 2.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const double root_angle = parameters.pose[0].norm();
  const Eigen::Matrix3d R_local = root_angle > 0 ? Eigen::AngleAxisd(root_angle, parameters.pose[0] / root_angle).toRotationMatrix()
                                                 : Eigen::Matrix3d::Identity();
  const Eigen::AngleAxisd root(R_w_b * R_local);
  parameters.pose[0] = root.angle() * root.axis();
  pf2::BodyMesh mesh = model.evaluate(parameters);
  Eigen::Vector3f lo = mesh.vertices[0], hi = mesh.vertices[0];
  for (const auto& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  for (auto& v : mesh.vertices) v.z() -= lo.z();  // feet on the floor
  pf2::RenderMesh render;
  render.vertices = mesh.vertices;
  render.triangles = mesh.triangles;
  render.colors.assign(mesh.vertices.size(), Eigen::Vector3f(colour[0], colour[1], colour[2]));
  render.label = 1;
  render.computeVertexNormals();
  pf2::CameraIntrinsics K;
  K.width = 240;
  K.height = 360;
  K.fx = K.fy = 330.0;
  K.cx = 119.5;
  K.cy = 179.5;
  // A fixed aim point 0.9 m above the floor, so that different statures compare.
  const Eigen::Vector3d centre(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), 0.9);
  const Eigen::Vector3d view(2.3 * std::sin(azimuth + 0.35), -2.3 * std::cos(azimuth + 0.35), 0.3);
  const Eigen::Isometry3d T_w_c = pf2::lookAt(centre + view, centre);
  pf2::Rasterizer::Options options;
  options.light_position_w = centre + 1.5 * view + Eigen::Vector3d(0.0, 0.0, 2.0);
  pf2::RenderedImages images;
  pf2::Rasterizer(options).render({&render}, {}, K, T_w_c, &images);
  images.bgr.setTo(cv::Scalar(235, 235, 235), images.labels == 0);
  return images.bgr;
}

void save(const std::string& path, const cv::Mat& image) {
  if (!cv::imwrite(path, image)) throw std::runtime_error("cannot write " + path);
  std::cout << "wrote " << path << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "Usage: pf2_synth_pictures OUT_DIR\n";
    return 1;
  }
  const std::string dir = std::string(argv[1]) + "/";
  try {
    pf2::SyntheticSequence::Options options;
    options.people = 3;
    const pf2::SyntheticSequence sequence(options);
    for (const int i : {40, 200}) {
      pf2::FrameGroundTruth truth;
      const pf2::Frame frame = sequence.frame(static_cast<size_t>(i), &truth);
      cv::Mat row;
      cv::hconcat(std::vector<cv::Mat>{frame.rgb, colourDepth(frame.depth), colourLabels(truth.labels)}, row);
      cv::resize(row, row, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
      save(dir + "synth_frame_" + std::to_string(i) + ".png", row);
    }

    const pf2::BodyModel model = pf2::BodyModel::loadDefault();
    const cv::Vec3f skin(0.62f, 0.72f, 0.86f);
    pf2::BodyParameters rest;
    pf2::BodyParameters walking;
    const double lowering = pf2::armLoweringAngle(model, walking.shape);
    const pf2::JointRotations gait = pf2::walkingPose(kPi / 2.0, 1.0, lowering);
    for (int j = 0; j < pf2::kBodyJointCount; ++j) walking.pose[j] = gait[j];
    pf2::BodyParameters sitting;
    const pf2::JointRotations seated = pf2::sittingPose(lowering);
    for (int j = 0; j < pf2::kBodyJointCount; ++j) sitting.pose[j] = seated[j];
    cv::Mat poses;
    cv::hconcat(std::vector<cv::Mat>{renderBody(model, rest, skin), renderBody(model, walking, skin, 0.9),
                                    renderBody(model, sitting, skin, 0.6)}, poses);
    save(dir + "body_poses.png", poses);
    pf2::BodyParameters a = walking, b = walking;
    a.shape.setZero();
    b.shape.setZero();
    a.shape[0] = 1.8;  // tall
    a.shape[3] = 1.8;  // and heavy
    b.shape[0] = -1.5;
    b.shape[3] = -1.5;
    cv::Mat shapes;
    cv::hconcat(std::vector<cv::Mat>{renderBody(model, a, cv::Vec3f(0.55f, 0.75f, 0.6f)),
                                     renderBody(model, b, cv::Vec3f(0.8f, 0.6f, 0.55f))}, shapes);
    save(dir + "body_shapes.png", shapes);
  } catch (const std::exception& e) {
    std::cerr << "pf2_synth_pictures: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
