#include "pf2/io/openni2_stream.h"

#include <pcl/pcl_config.h>

#include "pf2/core/error.h"
#include "pf2/io/frame_streams.h"
#include "pf2/io/tum_recorder.h"

#ifdef HAVE_OPENNI2
#include <pcl/io/openni2_grabber.h>
#include <pcl/io/openni2/openni2_device.h>

#include <opencv2/imgproc.hpp>
#endif

namespace pf2 {

#ifdef HAVE_OPENNI2

struct OpenNI2Stream::Impl {
  std::string device;
  std::unique_ptr<pcl::io::OpenNI2Grabber> grabber;
  LatestFrameSlot slot;
  std::unique_ptr<TumRecorder> recorder;
  CameraIntrinsics intrinsics;
  int index = 0;

  // The grabber's thread: one synchronised colour + depth pair into a Frame.
  void onImages(const pcl::io::Image::Ptr& image, const pcl::io::DepthImage::Ptr& depth) {
    try {
      Frame frame;
      frame.index = index++;
      frame.timestamp = static_cast<double>(depth->getTimestamp()) * 1e-6;  // microseconds
      cv::Mat rgb(image->getHeight(), image->getWidth(), CV_8UC3);
      image->fillRGB(rgb.cols, rgb.rows, rgb.data, static_cast<unsigned>(rgb.step));
      cv::cvtColor(rgb, frame.rgb, cv::COLOR_RGB2BGR);
      cv::Mat raw(depth->getHeight(), depth->getWidth(), CV_16U);
      depth->fillDepthImageRaw(raw.cols, raw.rows, raw.ptr<unsigned short>(), static_cast<unsigned>(raw.step));
      raw.convertTo(frame.depth, CV_32F, 1e-3);  // millimetres
      frame.intrinsics = intrinsics;
      frame.intrinsics.width = frame.rgb.cols;
      frame.intrinsics.height = frame.rgb.rows;
      if (recorder) recorder->add(frame);
      slot.put(std::move(frame));
    } catch (...) {
      slot.fail(std::current_exception());
    }
  }
};

OpenNI2Stream::OpenNI2Stream(const std::string& device, const std::string& record_dir) : impl_(new Impl) {
  impl_->device = device.empty() ? "the first OpenNI2 camera" : device;
  try {
    impl_->grabber = std::make_unique<pcl::io::OpenNI2Grabber>(device);
  } catch (const std::exception& e) {
    throw Error("OpenNI2 device '" + impl_->device + "': cannot open it (" + e.what() + ")");
  }
  if (!record_dir.empty()) impl_->recorder = std::make_unique<TumRecorder>(record_dir);
  // Depth is registered to colour by the driver: both images share the colour camera's model.
  const double f = impl_->grabber->getDevice()->getColorFocalLength();
  impl_->intrinsics.fx = impl_->intrinsics.fy = f > 0 ? f : 525.0;
  impl_->intrinsics.cx = 319.5;
  impl_->intrinsics.cy = 239.5;
  std::function<pcl::io::OpenNI2Grabber::sig_cb_openni_image_depth_image> callback =
      [this](const pcl::io::Image::Ptr& image, const pcl::io::DepthImage::Ptr& depth, float) {
        impl_->onImages(image, depth);
      };
  impl_->grabber->registerCallback(callback);
  try {
    impl_->grabber->start();
  } catch (const std::exception& e) {
    throw Error("OpenNI2 device '" + impl_->device + "': cannot start its streams (" + e.what() + ")");
  }
}

OpenNI2Stream::~OpenNI2Stream() { stop(); }

std::optional<Frame> OpenNI2Stream::next() { return impl_->slot.take(); }

void OpenNI2Stream::stop() {
  if (impl_->grabber && impl_->grabber->isRunning()) impl_->grabber->stop();
  impl_->slot.stop();
}

int OpenNI2Stream::dropped() const { return impl_->slot.dropped(); }

std::string OpenNI2Stream::description() const { return "OpenNI2 " + impl_->device; }

#else  // PCL built without OpenNI2

struct OpenNI2Stream::Impl {};

OpenNI2Stream::OpenNI2Stream(const std::string& device, const std::string&) {
  throw Error("OpenNI2 device '" + device + "': this build of PCL has no OpenNI2 support");
}
OpenNI2Stream::~OpenNI2Stream() = default;
std::optional<Frame> OpenNI2Stream::next() { return std::nullopt; }
void OpenNI2Stream::stop() {}
int OpenNI2Stream::dropped() const { return 0; }
std::string OpenNI2Stream::description() const { return "OpenNI2 (unavailable)"; }

#endif

}  // namespace pf2
