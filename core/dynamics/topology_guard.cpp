#include "dynamics/topology_guard.h"

#include "geometry/iso_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>

namespace rbfmuscle {

namespace {

/// Calls visit(next) for every one of the 14 Kuhn neighbours of node `id` (offsets in
/// {0, 1}³ \ {0} and their negatives, the edges of the extraction's tetrahedra) in the grid.
template <typename Visit>
void forEachNeighbour(const RegularGrid& grid, std::int64_t id, Visit&& visit) {
  static constexpr int kOffsets[7][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
  const std::int64_t nx = grid.counts[0], ny = grid.counts[1], nz = grid.counts[2];
  const std::int64_t i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
  for (const auto& o : kOffsets) {
    for (int sign = -1; sign <= 1; sign += 2) {
      const std::int64_t a = i + sign * o[0], b = j + sign * o[1], c = k + sign * o[2];
      if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
      visit(grid.index(a, b, c));
    }
  }
}

/// Whether node `id` lies on a face of the grid (outside for the extraction).
bool isOnFace(const RegularGrid& grid, std::int64_t id) {
  const std::int64_t nx = grid.counts[0], ny = grid.counts[1], nz = grid.counts[2];
  const std::int64_t i = id % nx, j = (id / nx) % ny, k = id / (nx * ny);
  return i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
}

}  // namespace

std::string toString(TopologyStop stop) {
  switch (stop) {
    case TopologyStop::kOnePiece: return "one_piece";
    case TopologyStop::kRoundCap: return "round_cap";
    case TopologyStop::kStuck: return "stuck";
    case TopologyStop::kDisabled: return "disabled";
  }
  return "unknown";
}

TopologyGuard::TopologyGuard(std::vector<bool> free_mask, Eigen::VectorXd max_abs_weights,
                             const TopologySettings& settings)
    : limits_{std::move(free_mask), std::move(max_abs_weights)}, settings_(settings) {
  if (limits_.max_abs_weights.size() != static_cast<Eigen::Index>(limits_.free_mask.size()) ||
      (limits_.max_abs_weights.array() < 0.0).any()) {
    throw std::invalid_argument("TopologyGuard: " + std::to_string(limits_.max_abs_weights.size()) +
                                " weight limits (expected one >= 0 per centre, " + std::to_string(limits_.free_mask.size()) + ")");
  }
  if (!(settings.cell_mm > 0.0) || !std::isfinite(settings.cell_mm)) {
    throw std::invalid_argument("TopologyGuard: cell_mm " + std::to_string(settings.cell_mm) + ", expected > 0");
  }
  if (settings.max_rounds < 1) {
    throw std::invalid_argument("TopologyGuard: max_rounds " + std::to_string(settings.max_rounds) + ", expected >= 1");
  }
  if (settings.bridge_nodes < 1) {
    throw std::invalid_argument("TopologyGuard: bridge_nodes " + std::to_string(settings.bridge_nodes) + ", expected >= 1");
  }
  if (!(settings.margin >= 0.0) || !std::isfinite(settings.margin)) {
    throw std::invalid_argument("TopologyGuard: margin " + std::to_string(settings.margin) + ", expected >= 0");
  }
  if (!(settings.crumb_join_level >= 0.0) || !std::isfinite(settings.crumb_join_level)) {
    throw std::invalid_argument("TopologyGuard: crumb_join_level " + std::to_string(settings.crumb_join_level) +
                                ", expected >= 0");
  }
  if (!(settings.neck_level >= 0.0) || !std::isfinite(settings.neck_level)) {
    throw std::invalid_argument("TopologyGuard: neck_level " + std::to_string(settings.neck_level) + ", expected >= 0");
  }
}

void TopologyGuard::updateValues(const GaussianField& field, const RegularGrid& grid) {
  const bool same_grid = grid.origin_mm == grid_.origin_mm && grid.cell_mm == grid_.cell_mm && grid.counts == grid_.counts;
  if (!same_grid || value_of_node_.size() != static_cast<size_t>(grid.size()) ||
      evaluated_centres_mm_.cols() != field.getNumCentres() || evaluated_centres_mm_ != field.getCentres() ||
      evaluated_shapes_ != field.getShapes() || evaluated_cutoff_ != field.getCutoff()) {
    grid_ = grid;
    calcValuesOnGrid(field, grid_, value_of_node_);
  } else {
    // Only weights and the offset changed since the last look (the guard's own rounds and
    // the volume step between passes): add their change instead of summing every centre.
    changed_centres_.clear();
    const Eigen::VectorXd& weights = field.getWeights();
    for (int k = 0; k < field.getNumCentres(); ++k)
      if (weights(k) != evaluated_weights_(k)) changed_centres_.push_back(k);
    weight_change_ = weights - evaluated_weights_;
    addCentresOnGrid(field, grid_, changed_centres_, weight_change_, value_of_node_);
    const double offset_change = field.getOffset() - evaluated_offset_;
    if (offset_change != 0.0)
      for (double& v : value_of_node_) v += offset_change;
  }
  evaluated_centres_mm_ = field.getCentres();
  evaluated_weights_ = field.getWeights();
  evaluated_shapes_ = field.getShapes();
  evaluated_offset_ = field.getOffset();
  evaluated_cutoff_ = field.getCutoff();
}

int TopologyGuard::label(const GaussianField& field, const Eigen::AlignedBox3d& box_mm, double level) {
  if (box_mm.isEmpty()) throw std::invalid_argument("TopologyGuard: empty box");
  // The nodes of extractIsoSurface.
  RegularGrid grid;
  grid.origin_mm = box_mm.min();
  grid.cell_mm = settings_.cell_mm;
  grid.counts = countIsoSurfaceNodes(box_mm, settings_.cell_mm);
  updateValues(field, grid);
  const std::int64_t nx = grid_.counts[0], ny = grid_.counts[1], nz = grid_.counts[2];
  // Inside nodes; box-face nodes count as outside, as in the extraction.
  piece_of_node_.assign(static_cast<size_t>(grid_.size()), kOutside);
  inside_ids_.clear();
  for (std::int64_t k = 1; k < nz - 1; ++k)
    for (std::int64_t j = 1; j < ny - 1; ++j)
      for (std::int64_t i = 1; i < nx - 1; ++i) {
        const std::int64_t id = grid_.index(i, j, k);
        if (value_of_node_[static_cast<size_t>(id)] > level) {
          piece_of_node_[static_cast<size_t>(id)] = kUnlabelled;
          inside_ids_.push_back(id);
        }
      }
  // Breadth-first growth from queue_ over the 14 Kuhn neighbours inside the grid: `take`
  // decides (and marks) whether a neighbour joins, `visit` sees every node that joined.
  auto grow = [&](auto&& take, auto&& visit) {
    for (size_t q = 0; q < queue_.size(); ++q) {
      const std::int64_t id = queue_[q];
      visit(id);
      forEachNeighbour(grid_, id, [&](std::int64_t next) {
        if (take(next)) queue_.push_back(next);
      });
    }
  };
  // A new piece from `seed`, tracking its size and its extreme node (highest or lowest f).
  auto startPiece = [&](std::int64_t seed) {
    piece_size_.push_back(0);
    piece_top_.push_back(seed);
    queue_.assign(1, seed);
  };
  auto track = [&](bool highest) {
    return [this, highest](std::int64_t id) {
      ++piece_size_.back();
      const double v = value_of_node_[static_cast<size_t>(id)];
      const double top = value_of_node_[static_cast<size_t>(piece_top_.back())];
      if (highest ? v > top : v < top) piece_top_.back() = id;
    };
  };
  // Pieces of {f > 0}, seeds in ascending node order.
  piece_size_.clear();
  piece_top_.clear();
  for (const std::int64_t seed : inside_ids_) {
    if (piece_of_node_[static_cast<size_t>(seed)] != kUnlabelled) continue;
    const int piece = static_cast<int>(piece_size_.size());
    piece_of_node_[static_cast<size_t>(seed)] = piece;
    startPiece(seed);
    grow(
        [&](std::int64_t next) {
          if (piece_of_node_[static_cast<size_t>(next)] != kUnlabelled) return false;
          piece_of_node_[static_cast<size_t>(next)] = piece;
          return true;
        },
        track(true));
  }
  const int pieces = static_cast<int>(piece_size_.size());
  if (level != 0.0) return pieces;
  // Cavities: pieces of {f ≤ 0} not joined to the box faces.
  exterior_.assign(static_cast<size_t>(grid_.size()), 0);
  auto takeNegative = [&](std::int64_t next) {
    if (exterior_[static_cast<size_t>(next)] != 0 || piece_of_node_[static_cast<size_t>(next)] != kOutside) return false;
    exterior_[static_cast<size_t>(next)] = 1;
    return true;
  };
  queue_.clear();
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        if (i != 0 && j != 0 && k != 0 && i != nx - 1 && j != ny - 1 && k != nz - 1) continue;
        const std::int64_t id = grid_.index(i, j, k);
        exterior_[static_cast<size_t>(id)] = 1;
        queue_.push_back(id);
      }
  grow(takeNegative, [](std::int64_t) {});
  for (std::int64_t seed = 0; seed < grid_.size(); ++seed) {
    if (!takeNegative(seed)) continue;
    startPiece(seed);
    grow(takeNegative, track(false));
  }
  return pieces;
}

int TopologyGuard::countPieces(const GaussianField& field, const Eigen::AlignedBox3d& box_mm) {
  label(field, box_mm, 0.0);
  return static_cast<int>(piece_size_.size());
}

bool TopologyGuard::changeValueAt(const GaussianField& field, const Eigen::Vector3d& x_mm, double change,
                                  Eigen::VectorXd& weights, TopologyReport& report) {
  const int changed = rbfmuscle::changeValueAt(field, x_mm, change, limits_, weights, active_);
  report.weights_changed += changed;
  return changed > 0;
}

void TopologyGuard::findGapNodes(int island, int body, std::vector<std::int64_t>& gap) {
  // Closest pair of nodes (island, body), the body searched within the island's box
  // grown by kReach_mm; then the outside nodes on the segment between them. Nodes, not
  // the lowest point between nodes: the pieces the extraction bounds are joined through
  // nodes, so raising a point between two outside nodes would join nothing.
  constexpr double kReach_mm = 40.0;
  Eigen::AlignedBox3d island_box;
  island_nodes_.clear();
  for (const std::int64_t id : inside_ids_) {
    if (piece_of_node_[static_cast<size_t>(id)] != island) continue;
    island_nodes_.push_back(id);
    island_box.extend(grid_.node(id));
  }
  const Eigen::AlignedBox3d search(island_box.min().array() - kReach_mm, island_box.max().array() + kReach_mm);
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector3d from = island_box.center(), to = island_box.center();
  for (const std::int64_t b : inside_ids_) {
    if (piece_of_node_[static_cast<size_t>(b)] != body) continue;
    const Eigen::Vector3d xb = grid_.node(b);
    if (!search.contains(xb)) continue;
    for (const std::int64_t a : island_nodes_) {
      const double d2 = (grid_.node(a) - xb).squaredNorm();
      if (d2 < best) {
        best = d2;
        from = grid_.node(a);
        to = xb;
      }
    }
  }
  const int steps = std::max(2, static_cast<int>(std::ceil(2.0 * std::sqrt(best) / grid_.cell_mm)));
  gap.clear();
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector3d u = (from + (to - from) * (double(i) / steps) - grid_.origin_mm) / grid_.cell_mm;
    const std::int64_t id = grid_.index(std::lround(u.x()), std::lround(u.y()), std::lround(u.z()));
    if (value_of_node_[static_cast<size_t>(id)] <= 0.0 && (gap.empty() || gap.back() != id)) gap.push_back(id);
  }
}

double TopologyGuard::valueWithChanges(const GaussianField& field, const Eigen::VectorXd& weights,
                                       std::int64_t node) {
  field.findActiveCentres(grid_.node(node), active_);
  double value = value_of_node_[static_cast<size_t>(node)];
  for (int a = 0; a < active_.size(); ++a) {
    const int k = active_.indices[static_cast<size_t>(a)];
    value += (weights(k) - field.getWeights()(k)) * active_.phi[static_cast<size_t>(a)];
  }
  return value;
}

bool TopologyGuard::raiseNecks(const GaussianField& field, const Eigen::AlignedBox3d& box_mm, Eigen::VectorXd& weights,
                               TopologyReport& report) {
  const double level = settings_.neck_level;
  const int pieces = label(field, box_mm, level);
  if (pieces < 2) return false;
  const int body = static_cast<int>(std::max_element(piece_size_.begin(), piece_size_.end()) - piece_size_.begin());
  bool changed = false;
  for (int piece = 0; piece < pieces; ++piece) {
    if (piece == body || piece_size_[static_cast<size_t>(piece)] < settings_.bridge_nodes) continue;
    // Widest path through {f > 0} from the piece to the body (largest smallest value on
    // the way): the neck the surface still has, whose thinnest nodes are raised.
    bottleneck_.assign(static_cast<size_t>(grid_.size()), -std::numeric_limits<double>::infinity());
    predecessor_.assign(static_cast<size_t>(grid_.size()), -1);
    std::priority_queue<std::pair<double, std::int64_t>> frontier;
    for (const std::int64_t id : inside_ids_) {
      if (piece_of_node_[static_cast<size_t>(id)] != piece) continue;
      bottleneck_[static_cast<size_t>(id)] = std::numeric_limits<double>::infinity();
      frontier.push({std::numeric_limits<double>::infinity(), id});
    }
    std::int64_t reached = -1;
    while (!frontier.empty()) {
      const auto [width, id] = frontier.top();
      frontier.pop();
      if (width < bottleneck_[static_cast<size_t>(id)]) continue;
      if (piece_of_node_[static_cast<size_t>(id)] == body) {
        reached = id;
        break;
      }
      forEachNeighbour(grid_, id, [&, width = width, id = id](std::int64_t next) {
        const double v = value_of_node_[static_cast<size_t>(next)];
        if (!(v > 0.0) || isOnFace(grid_, next)) return;
        const double through = std::min(width, v);
        if (through > bottleneck_[static_cast<size_t>(next)]) {
          bottleneck_[static_cast<size_t>(next)] = through;
          predecessor_[static_cast<size_t>(next)] = id;
          frontier.push({through, next});
        }
      });
    }
    if (reached < 0) continue;  // joined at 0 through nothing inside the grid: the island rules apply
    bool raised = false;
    for (std::int64_t id = reached; id >= 0; id = predecessor_[static_cast<size_t>(id)]) {
      const double now = valueWithChanges(field, weights, id);
      if (now < level) raised |= changeValueAt(field, grid_.node(id), kNeckRaise * level - now, weights, report);
    }
    if (raised) {
      changed = true;
      ++report.necks_raised;
    }
  }
  return changed;
}

TopologyReport TopologyGuard::run(GaussianField& field, const Eigen::AlignedBox3d& box_mm) {
  TopologyReport report;
  if (!settings_.enabled) return report;
  if (static_cast<int>(limits_.free_mask.size()) != field.getNumCentres()) {
    throw std::invalid_argument("TopologyGuard::run: mask of " + std::to_string(limits_.free_mask.size()) +
                                " centres, field has " + std::to_string(field.getNumCentres()));
  }
  Eigen::VectorXd weights = field.getWeights();
  bool necks_checked = false;
  for (int round = 0;; ++round) {
    const int pieces = label(field, box_mm, 0.0);
    const int islands = std::max(0, pieces - 1);
    const int cavities = static_cast<int>(piece_size_.size()) - pieces;
    report.rounds = round + 1;
    report.grid_nodes = grid_.size();
    if (round == 0) {
      report.islands_found = islands;
      report.cavities_found = cavities;
    }
    report.defects_left = islands + cavities;
    if (report.defects_left == 0) {
      if (settings_.neck_level > 0.0 && !necks_checked && round < settings_.max_rounds) {
        necks_checked = true;
        if (raiseNecks(field, box_mm, weights, report)) {
          field.setWeights(weights);
          continue;
        }
      }
      report.stop_reason = TopologyStop::kOnePiece;
      break;
    }
    if (round == settings_.max_rounds) {
      report.stop_reason = TopologyStop::kRoundCap;
      break;
    }
    const int body = static_cast<int>(std::max_element(piece_size_.begin(), piece_size_.begin() + pieces) -
                                      piece_size_.begin());
    bool changed = false;
    for (int piece = 0; piece < static_cast<int>(piece_size_.size()); ++piece) {
      if (piece == body) continue;
      const std::int64_t node = piece_top_[static_cast<size_t>(piece)];
      const double value = value_of_node_[static_cast<size_t>(node)];
      if (piece >= pieces) {  // cavity: its lowest node up to +margin
        changed |= changeValueAt(field, grid_.node(node), settings_.margin - value, weights, report);
      } else {
        // A piece of muscle is joined back (its gap up to +margin); a crumb is removed (its top
        // down to −margin), unless it lies beside the body (a gap of at most kCrumbGapNodes nodes)
        // and joining it (its gap up to crumb_join_level) changes f less at every node.
        const bool crumb = piece_size_[static_cast<size_t>(piece)] < settings_.bridge_nodes;
        const double join_level = crumb ? settings_.crumb_join_level : settings_.margin;
        gap_nodes_.clear();  // a crumb's gap is looked for only when it may be joined
        if (!crumb || join_level > 0.0) findGapNodes(piece, body, gap_nodes_);
        double deepest_gap = 0.0;
        for (const std::int64_t gap : gap_nodes_) deepest_gap = std::min(deepest_gap, value_of_node_[static_cast<size_t>(gap)]);
        const bool join = !crumb || (!gap_nodes_.empty() && gap_nodes_.size() <= kCrumbGapNodes &&
                                     join_level - deepest_gap < value + settings_.margin);
        bool joined = false;
        if (join) {
          for (const std::int64_t gap : gap_nodes_) {
            const double now = valueWithChanges(field, weights, gap);  // an earlier raise may have lifted it
            if (now <= 0.0) joined |= changeValueAt(field, grid_.node(gap), join_level - now, weights, report);
          }
        }
        if (joined) {
          changed = true;
          ++report.islands_bridged;
        } else {  // a crumb, or no weight can raise the gap (all at their limits): removed
          changed |= changeValueAt(field, grid_.node(node), -(value + settings_.margin), weights, report);
          ++report.islands_removed;
        }
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
