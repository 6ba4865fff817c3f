#include "pf2/slam/slam_runner.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <thread>

#include "pf2/core/error.h"
#include "pf2/core/work_queue.h"

namespace pf2 {

namespace {

// A frame with its people, handed from the detection thread to the front end; or the error that
// ended the detection thread.
struct DetectedFrame {
  Frame frame;
  Detections detections;
  std::exception_ptr error;
};

bool stopRequested(const std::atomic<bool>* stop) { return stop != nullptr && stop->load(); }

}  // namespace

void SlamRunner::showProgress(size_t expected, int dropped, double seconds) const {
  const SlamRunSummary& s = system_->progress();
  if (!options_.progress || (s.frames % 30 != 0 && static_cast<size_t>(s.frames) != expected)) return;
  std::fprintf(stderr, "\rframe %d", s.frames);
  if (expected > 0) std::fprintf(stderr, "/%zu", expected);
  std::fprintf(stderr, "  %.1f fps  lost %d  keyframes %zu", s.frames / std::max(seconds, 1e-9), s.lost,
               system_->keyframeCount());
  if (dropped > 0) std::fprintf(stderr, "  dropped %d", dropped);
  std::fprintf(stderr, "   ");
}

// The two threads: detection (stream -> detect -> queue) and the front end (queue -> process).
void SlamRunner::processAll(FrameStream* stream, const std::atomic<bool>* stop) {
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  if (!options_.detect_ahead) {
    while (!stopRequested(stop)) {
      std::optional<Frame> frame = stream->next();
      if (!frame) break;
      system_->process(*frame, system_->detect(*frame));
      showProgress(stream->expected(), stream->dropped(), seconds());
    }
    return;
  }
  WorkQueue<DetectedFrame> queue(2);
  std::thread detection([&] {
    try {
      while (!stopRequested(stop)) {
        std::optional<Frame> frame = stream->next();
        if (!frame) break;
        Detections detections = system_->detect(*frame);
        queue.push({std::move(*frame), std::move(detections), nullptr});
      }
    } catch (...) {
      queue.push({Frame(), Detections(), std::current_exception()});
    }
    queue.close();
  });
  try {
    while (std::optional<DetectedFrame> item = queue.pop()) {
      if (item->error) std::rethrow_exception(item->error);
      system_->process(item->frame, item->detections);
      showProgress(stream->expected(), stream->dropped(), seconds());
    }
  } catch (...) {
    stream->stop();
    queue.close();
    detection.join();
    throw;
  }
  detection.join();
}

SlamResult SlamRunner::run(FrameStream* stream, const std::atomic<bool>* stop) {
  try {
    processAll(stream, stop);
  } catch (...) {
    system_->abandon();
    throw;
  }
  stream->stop();
  if (options_.progress) std::fprintf(stderr, "\n");
  SlamResult result = system_->finish();
  result.summary.dropped = stream->dropped();
  result.summary.stopped = stopRequested(stop);
  return result;
}

void makeOutputFolder(const std::string& out_dir) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(out_dir, error)) return;
  if (fs::exists(out_dir, error)) throw fileError(out_dir, "output path exists and is not a folder");
  // Not recursive: a mistyped parent folder is an error, not a tree of new folders.
  if (!fs::create_directory(out_dir, error)) throw fileError(out_dir, "cannot create the output folder");
}

SlamResult runToFolder(SlamSystem* system, FrameStream* stream, const std::string& out_dir,
                       const SlamRunner::Options& options, const std::atomic<bool>* stop,
                       const ExtraFiles& extra_files) {
  namespace fs = std::filesystem;
  std::error_code ignored;
  makeOutputFolder(out_dir);
  // Masks are written as frames pass, into a folder renamed to masks/ once the run succeeded.
  const std::string masks_partial = out_dir + "/masks.partial";
  const bool masks = system->options().write_masks && system->removesPeople();
  if (masks) {
    fs::remove_all(masks_partial, ignored);
    if (!fs::create_directory(masks_partial, ignored)) throw fileError(masks_partial, "cannot create the folder");
    system->writeMasksTo(masks_partial);
  }
  try {
    const SlamResult result = SlamRunner(system, options).run(stream, stop);
    writeSlamResult(out_dir, result, &system->stats(), extra_files);
    // An earlier run's masks/ goes either way: it does not belong to this run's files.
    fs::remove_all(out_dir + "/masks");
    if (masks) fs::rename(masks_partial, out_dir + "/masks");
    return result;
  } catch (...) {
    fs::remove_all(masks_partial, ignored);
    throw;
  }
}

}  // namespace pf2
