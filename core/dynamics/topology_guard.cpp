#include "dynamics/topology_guard.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rbfmuscle {

std::string toString(TopologyStop stop) {
  switch (stop) {
    case TopologyStop::kOnePiece: return "one_piece";
    case TopologyStop::kRoundCap: return "round_cap";
    case TopologyStop::kStuck: return "stuck";
    case TopologyStop::kDisabled: return "disabled";
  }
  return "unknown";
}

TopologyGuard::TopologyGuard(std::vector<bool> free_mask, const TopologySettings& settings)
    : free_mask_(std::move(free_mask)), settings_(settings) {
  if (!(settings.cell_mm > 0.0) || !std::isfinite(settings.cell_mm)) {
    throw std::invalid_argument("TopologyGuard: cell_mm " + std::to_string(settings.cell_mm) + ", expected > 0");
  }
  if (settings.max_rounds < 1) {
    throw std::invalid_argument("TopologyGuard: max_rounds " + std::to_string(settings.max_rounds) + ", expected >= 1");
  }
  if (!(settings.margin >= 0.0) || !std::isfinite(settings.margin)) {
    throw std::invalid_argument("TopologyGuard: margin " + std::to_string(settings.margin) + ", expected >= 0");
  }
}

int TopologyGuard::label(const GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                         const Eigen::Matrix3Xd& support_mm, double support_radius_mm) {
  if (box_mm.isEmpty()) throw std::invalid_argument("TopologyGuard: empty box");
  const double h = settings_.cell_mm;
  // The node layout of extractIsoSurface (geometry/iso_surface.cpp).
  for (int a = 0; a < 3; ++a) {
    counts_[a] = std::max<std::int64_t>(2, std::int64_t(std::ceil(box_mm.sizes()[a] / h - 1e-9)) + 1);
  }
  const std::int64_t nx = counts_[0], ny = counts_[1], nz = counts_[2];
  grid_nodes_ = nx * ny * nz;
  auto nodeOf = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return i + nx * (j + ny * k); };
  // Nodes within the support cubes, without the box faces (outside, as in the extraction).
  piece_of_node_.assign(static_cast<size_t>(grid_nodes_), kOutside);
  const std::int64_t reach = std::int64_t(std::ceil(support_radius_mm / h));
  std::int64_t looked = 0;
  for (Eigen::Index q = 0; q < support_mm.cols(); ++q) {
    const Eigen::Vector3d g = (support_mm.col(q) - box_mm.min()) / h;
    const std::int64_t ci = std::llround(g.x()), cj = std::llround(g.y()), ck = std::llround(g.z());
    for (std::int64_t k = std::max<std::int64_t>(1, ck - reach); k <= std::min(nz - 2, ck + reach); ++k)
      for (std::int64_t j = std::max<std::int64_t>(1, cj - reach); j <= std::min(ny - 2, cj + reach); ++j)
        for (std::int64_t i = std::max<std::int64_t>(1, ci - reach); i <= std::min(nx - 2, ci + reach); ++i) {
          int& state = piece_of_node_[static_cast<size_t>(nodeOf(i, j, k))];
          if (state == kOutside) {
            state = kUnlabelled;
            ++looked;
          }
        }
  }
  looked_nodes_ = looked;
  looked_ids_.clear();
  looked_ids_.reserve(static_cast<size_t>(looked));
  for (std::int64_t id = 0; id < grid_nodes_; ++id)
    if (piece_of_node_[static_cast<size_t>(id)] == kUnlabelled) looked_ids_.push_back(id);
  points_mm_.resize(3, static_cast<Eigen::Index>(looked_ids_.size()));
  for (size_t q = 0; q < looked_ids_.size(); ++q) {
    const std::int64_t id = looked_ids_[q];
    points_mm_.col(static_cast<Eigen::Index>(q)) =
        box_mm.min() + h * Eigen::Vector3d(double(id % nx), double((id / nx) % ny), double(id / (nx * ny)));
  }
  field.calcValues(points_mm_, values_);
  value_of_node_.assign(static_cast<size_t>(grid_nodes_), 0.0);
  for (size_t q = 0; q < looked_ids_.size(); ++q) {
    const std::int64_t id = looked_ids_[q];
    const double v = values_(static_cast<Eigen::Index>(q));
    value_of_node_[static_cast<size_t>(id)] = v;
    if (!(v > 0.0)) piece_of_node_[static_cast<size_t>(id)] = kOutside;
  }
  // Pieces: breadth-first over the 14 Kuhn neighbours, seeds in ascending node order.
  static constexpr int kOffsets[7][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
  piece_size_.clear();
  piece_top_.clear();
  for (const std::int64_t seed : looked_ids_) {
    if (piece_of_node_[static_cast<size_t>(seed)] != kUnlabelled) continue;
    const int piece = static_cast<int>(piece_size_.size());
    piece_size_.push_back(0);
    piece_top_.push_back(seed);
    queue_.assign(1, seed);
    piece_of_node_[static_cast<size_t>(seed)] = piece;
    for (size_t q = 0; q < queue_.size(); ++q) {
      const std::int64_t id = queue_[q];
      ++piece_size_.back();
      if (value_of_node_[static_cast<size_t>(id)] > value_of_node_[static_cast<size_t>(piece_top_.back())])
        piece_top_.back() = id;
      const std::int64_t i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
      for (const auto& o : kOffsets) {
        for (int sign = -1; sign <= 1; sign += 2) {
          const std::int64_t next = nodeOf(i + sign * o[0], j + sign * o[1], k + sign * o[2]);
          // Box-face and unlooked nodes are kOutside, so no bounds test is needed
          // beyond the faces, which no interior node's neighbour passes.
          if (piece_of_node_[static_cast<size_t>(next)] != kUnlabelled) continue;
          piece_of_node_[static_cast<size_t>(next)] = piece;
          queue_.push_back(next);
        }
      }
    }
  }
  const int pieces = static_cast<int>(piece_size_.size());
  // Cavities: pieces of {f ≤ 0} (unlooked nodes included) not joined to the box faces.
  exterior_.assign(static_cast<size_t>(grid_nodes_), 0);
  auto isNegative = [&](std::int64_t id) { return piece_of_node_[static_cast<size_t>(id)] == kOutside; };
  auto flood = [&](int mark, bool track) {
    for (size_t q = 0; q < queue_.size(); ++q) {
      const std::int64_t id = queue_[q];
      if (track) {
        ++piece_size_.back();
        if (value_of_node_[static_cast<size_t>(id)] < value_of_node_[static_cast<size_t>(piece_top_.back())])
          piece_top_.back() = id;
      }
      const std::int64_t i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
      for (const auto& o : kOffsets) {
        for (int sign = -1; sign <= 1; sign += 2) {
          const std::int64_t a = i + sign * o[0], b = j + sign * o[1], c = k + sign * o[2];
          if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
          const std::int64_t next = nodeOf(a, b, c);
          if (exterior_[static_cast<size_t>(next)] != 0 || !isNegative(next)) continue;
          exterior_[static_cast<size_t>(next)] = static_cast<std::uint8_t>(mark);
          queue_.push_back(next);
        }
      }
    }
  };
  queue_.clear();
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        if (i != 0 && j != 0 && k != 0 && i != nx - 1 && j != ny - 1 && k != nz - 1) continue;
        const std::int64_t id = nodeOf(i, j, k);
        exterior_[static_cast<size_t>(id)] = 1;
        queue_.push_back(id);
      }
  flood(1, false);
  first_cavity_ = pieces;
  for (const std::int64_t seed : looked_ids_) {
    if (exterior_[static_cast<size_t>(seed)] != 0 || !isNegative(seed)) continue;
    piece_size_.push_back(0);
    piece_top_.push_back(seed);
    exterior_[static_cast<size_t>(seed)] = 2;
    queue_.assign(1, seed);
    flood(2, true);
  }
  return pieces;
}

int TopologyGuard::countPieces(const GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                               const Eigen::Matrix3Xd& support_mm, double support_radius_mm) {
  return label(field, box_mm, support_mm, support_radius_mm);
}

TopologyReport TopologyGuard::run(GaussianField& field, const Eigen::AlignedBox3d& box_mm,
                                  const Eigen::Matrix3Xd& support_mm, double support_radius_mm) {
  TopologyReport report;
  if (!settings_.enabled) return report;
  if (static_cast<int>(free_mask_.size()) != field.getNumCentres()) {
    throw std::invalid_argument("TopologyGuard::run: mask of " + std::to_string(free_mask_.size()) +
                                " centres, field has " + std::to_string(field.getNumCentres()));
  }
  Eigen::VectorXd weights = field.getWeights();
  for (int round = 0;; ++round) {
    const int pieces = label(field, box_mm, support_mm, support_radius_mm);
    const int islands = std::max(0, pieces - 1);
    const int cavities = static_cast<int>(piece_size_.size()) - pieces;
    report.rounds = round + 1;
    report.grid_nodes = grid_nodes_;
    report.looked_nodes = looked_nodes_;
    if (round == 0) {
      report.islands_found = islands;
      report.cavities_found = cavities;
    }
    report.defects_left = islands + cavities;
    if (report.defects_left == 0) {
      report.stop_reason = TopologyStop::kOnePiece;
      break;
    }
    if (round == settings_.max_rounds) {
      report.stop_reason = TopologyStop::kRoundCap;
      break;
    }
    const auto body = std::max_element(piece_size_.begin(), piece_size_.begin() + pieces) - piece_size_.begin();
    bool changed = false;
    for (int piece = 0; piece < static_cast<int>(piece_size_.size()); ++piece) {
      if (piece == body) continue;
      const std::int64_t node = piece_top_[static_cast<size_t>(piece)];
      // Islands go down to −margin, cavities up to +margin.
      const double value = value_of_node_[static_cast<size_t>(node)];
      const double change = piece < pieces ? -(value + settings_.margin) : settings_.margin - value;
      const std::int64_t nx = counts_[0], ny = counts_[1];
      const Eigen::Vector3d x = box_mm.min() + settings_.cell_mm * Eigen::Vector3d(double(node % nx), double((node / nx) % ny),
                                                                                  double(node / (nx * ny)));
      field.findActiveCentres(x, active_);
      // The free centres active at x*; only if there are none, the attached ones too.
      for (const bool free_only : {true, false}) {
        double norm = 0.0;  // Σ |λ| φ²
        for (int a = 0; a < active_.size(); ++a) {
          const int k = active_.indices[static_cast<size_t>(a)];
          const double phi = active_.phi[static_cast<size_t>(a)];
          if (!free_only || free_mask_[static_cast<size_t>(k)]) norm += std::abs(weights(k)) * phi * phi;
        }
        if (!(norm > 0.0)) continue;
        for (int a = 0; a < active_.size(); ++a) {
          const int k = active_.indices[static_cast<size_t>(a)];
          if (free_only && !free_mask_[static_cast<size_t>(k)]) continue;
          // A weight changes by Δf |λ| φ / Σ|λ|φ² and never changes sign (the fit's sign rule).
          const double updated = weights(k) + change * std::abs(weights(k)) * active_.phi[static_cast<size_t>(a)] / norm;
          weights(k) = weights(k) > 0.0 ? std::max(0.0, updated) : std::min(0.0, updated);
          ++report.weights_changed;
          changed = true;
        }
        break;
      }
    }
    if (!changed) {
      report.stop_reason = TopologyStop::kStuck;
      break;
    }
    field.setWeights(weights);
  }
  return report;
}

}  // namespace rbfmuscle
