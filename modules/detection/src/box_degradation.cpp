#include "pf2/detection/box_degradation.h"

#include <algorithm>
#include <cmath>

#include "pf2/core/settings.h"

namespace pf2 {

void declareBoxDegradationSettings(const std::string& prefix, BoxDegradation* d, Settings* settings) {
  settings->number(prefix + "shrink", &d->shrink, 0.0, 0.9, "fraction", "boxes lose this fraction of their width and height");
  settings->number(prefix + "shift", &d->shift, 0.0, 200.0, "pixels", "boxes (and masks) move this far in a random direction");
  settings->number(prefix + "drop", &d->drop_probability, 0.0, 1.0, "probability", "each person is missed with this probability");
  settings->number(prefix + "false_positives", &d->false_positive_rate, 0.0, 20.0, "boxes per frame",
                   "mean number of false boxes added per frame");
  settings->seed(prefix + "seed", &d->seed, "seed of the degradation's random choices");
}
namespace {

// splitmix64: tiny, and its sequence is the same on every platform (std distributions are not).
class Random {
 public:
  explicit Random(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int poisson(double mean) {  // Knuth; means here are small
    const double limit = std::exp(-mean);
    int k = 0;
    for (double p = uniform(); p > limit; p *= uniform()) ++k;
    return k;
  }

 private:
  uint64_t state_;
};

PersonBox clipped(PersonBox b, const cv::Size& image) {
  b.x_ul = std::clamp(b.x_ul, 0.f, static_cast<float>(image.width));
  b.x_lr = std::clamp(b.x_lr, 0.f, static_cast<float>(image.width));
  b.y_ul = std::clamp(b.y_ul, 0.f, static_cast<float>(image.height));
  b.y_lr = std::clamp(b.y_lr, 0.f, static_cast<float>(image.height));
  return b;
}

}  // namespace

void degradeDetections(const BoxDegradation& d, const cv::Size& image, Detections* detections) {
  if (!d.active()) return;
  // The frame's draws depend on the seed and its stamp (microseconds) only.
  const uint64_t stamp = static_cast<uint64_t>(std::llround(detections->timestamp * 1e6));
  Random random(d.seed * 0x2545F4914F6CDD1Dull ^ stamp);
  std::vector<PersonDetection> kept;
  for (PersonDetection& person : detections->people) {
    // Every person consumes the same draws whatever happens to it, so one person's fate does not
    // change another's.
    const double drop = random.uniform();
    const double angle = random.uniform(0.0, 2.0 * M_PI);
    if (drop < d.drop_probability) continue;
    PersonBox& b = person.box;
    const float cu = 0.5f * (b.x_ul + b.x_lr), cv_ = 0.5f * (b.y_ul + b.y_lr);
    const float keep = static_cast<float>(std::max(0.0, 1.0 - d.shrink));
    const float hw = 0.5f * keep * b.width(), hh = 0.5f * keep * b.height();
    const float du = static_cast<float>(d.shift * std::cos(angle));
    const float dv = static_cast<float>(d.shift * std::sin(angle));
    b = clipped(PersonBox{cu - hw + du, cv_ - hh + dv, cu + hw + du, cv_ + hh + dv}, image);
    if (!person.mask.empty() && d.shift > 0) {
      cv::Mat moved = cv::Mat::zeros(person.mask.size(), person.mask.type());
      const int su = static_cast<int>(std::round(du)), sv = static_cast<int>(std::round(dv));
      const cv::Rect src = cv::Rect(-su, -sv, person.mask.cols, person.mask.rows) &
                           cv::Rect(0, 0, person.mask.cols, person.mask.rows);
      if (!src.empty()) person.mask(src).copyTo(moved(src + cv::Point(su, sv)));
      person.mask = moved;
    }
    if (b.empty()) continue;
    kept.push_back(std::move(person));
  }
  const int false_positives = d.false_positive_rate > 0 ? random.poisson(d.false_positive_rate) : 0;
  for (int i = 0; i < false_positives; ++i) {
    const double h = random.uniform(80.0, 320.0), w = 0.4 * h;
    const double u = random.uniform(0.0, std::max(1.0, image.width - w));
    const double v = random.uniform(0.0, std::max(1.0, image.height - h));
    PersonDetection fake;
    fake.box = clipped(PersonBox{static_cast<float>(u), static_cast<float>(v), static_cast<float>(u + w),
                                 static_cast<float>(v + h)}, image);
    fake.score = static_cast<float>(random.uniform(0.5, 1.0));
    if (fake.score <= 0.5f) fake.score = 0.51f;
    if (!fake.box.empty()) kept.push_back(std::move(fake));
  }
  detections->people = std::move(kept);
}

}  // namespace pf2
