// SPDX-License-Identifier: Apache-2.0
#include "model/moment_arms.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace rbfmuscle {

std::vector<int> parseCoordinateList(const std::string& text, const Skeleton& skeleton) {
  std::vector<int> out;
  std::stringstream in(text);
  for (std::string name; std::getline(in, name, ',');) {
    const auto b = name.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) continue;
    name = name.substr(b, name.find_last_not_of(" \t\r\n") - b + 1);
    if (name == "all") {
      for (int c = 0; c < static_cast<int>(skeleton.getCoordinateNames().size()); ++c) out.push_back(c);
      continue;
    }
    const int c = skeleton.findCoordinateIndex(name);
    if (c < 0) {
      std::string names;
      for (const std::string& n : skeleton.getCoordinateNames()) names += (names.empty() ? "" : ", ") + n;
      throw ModelError("no coordinate '" + name + "' in the skeleton " + skeleton.getModelPath() + " (it has: " +
                       names + "; or write 'all')");
    }
    out.push_back(c);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

MomentArms::MomentArms(const Skeleton& skeleton, std::vector<int> coordinates)
    : probe_(std::make_unique<Skeleton>(Skeleton::fromFile(skeleton.getModelPath()))),
      coordinates_(std::move(coordinates)),
      arms_(coordinates_.size()) {
  probe_->setRestCoordinateValues(skeleton.getRestCoordinateValues());
}

MomentArms::~MomentArms() = default;

void MomentArms::update(const Eigen::VectorXd& q, const Measure& measure) {
  const std::vector<CoordinateInfo>& info = probe_->getCoordinates();
  Eigen::Index size = -1;
  for (size_t k = 0; k < coordinates_.size(); ++k) {
    const int c = coordinates_[k];
    const double step =
        info[static_cast<size_t>(c)].motion == CoordinateMotion::kRotational ? kMomentArmStep_rad : kMomentArmStep_mm;
    Eigen::VectorXd lengths[2];
    for (int side = 0; side < 2; ++side) {
      Eigen::VectorXd probe_q = q;
      probe_q[c] += side == 0 ? step : -step;
      probe_->setCoordinateValues(probe_q);
      lengths[side] = measure(*probe_, probe_q);
      if (size < 0) size = lengths[side].size();
      if (lengths[side].size() != size)
        throw std::invalid_argument("MomentArms: a measurement gave " + std::to_string(lengths[side].size()) +
                                    " lengths, the first " + std::to_string(size));
    }
    arms_[k] = (lengths[1] - lengths[0]) / (2.0 * step);  // −∂l/∂q
  }
}

}  // namespace rbfmuscle
