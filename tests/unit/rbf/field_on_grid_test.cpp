// The separable grid evaluation against the field's own point evaluation.
#include "rbf/field_on_grid.h"

#include "rbf_test_fields.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace rbfmuscle {
namespace {

/// Every node of a grid that cuts through the centres, against calcValue.
void expectMatchesPointValues(const GaussianField& field, const RegularGrid& grid, const std::vector<double>& values) {
  ASSERT_EQ(static_cast<std::int64_t>(values.size()), grid.size());
  double scale = std::abs(field.getOffset());
  for (int k = 0; k < field.getNumCentres(); ++k) scale += std::abs(field.getWeights()(k));
  for (std::int64_t id = 0; id < grid.size(); ++id) {
    ASSERT_NEAR(values[static_cast<size_t>(id)], field.calcValue(grid.node(id)), 1e-13 * scale) << "node " << id;
  }
}

void expectMatchesPointValues(const GaussianField& field, const RegularGrid& grid) {
  std::vector<double> values;
  calcValuesOnGrid(field, grid, values);
  expectMatchesPointValues(field, grid, values);
}

/// A grid over the random test fields' centres (placed within ±20 mm of the origin).
RegularGrid gridThroughTheCentres() {
  RegularGrid grid;
  grid.origin_mm = Eigen::Vector3d(-23.3, -19.1, -21.7);
  grid.cell_mm = 1.7;
  grid.counts = {28, 25, 27};
  return grid;
}

TEST(FieldOnGrid, EqualsPointValuesWithAndWithoutCutoff) {
  std::mt19937 rng(7);
  GaussianField field = test::makeRandomField(rng, 60, 0.005, 2.0, 20.0, 1e-8);
  const RegularGrid grid = gridThroughTheCentres();
  expectMatchesPointValues(field, grid);
  field.setCutoff(1e-3);  // a coarse cut-off: the same centres must be left out
  expectMatchesPointValues(field, grid);
  field.setCutoff(0.0);
  expectMatchesPointValues(field, grid);
}

// A few weights changed: adding their change to the old grid values gives the new
// field's values (what the topology guard does between its rounds).
TEST(FieldOnGrid, AddingChangedWeightsEqualsNewValues) {
  std::mt19937 rng(11);
  GaussianField field = test::makeRandomField(rng, 60, 0.005, 2.0, 20.0, 1e-8);
  const RegularGrid grid = gridThroughTheCentres();
  std::vector<double> values;
  calcValuesOnGrid(field, grid, values);
  Eigen::VectorXd change = Eigen::VectorXd::Zero(field.getNumCentres());
  const std::vector<int> changed = {3, 17, 42};
  for (int k : changed) change(k) = 0.5 * field.getWeights()(k) + 0.3;
  addCentresOnGrid(field, grid, changed, change, values);
  field.setWeights(field.getWeights() + change);
  expectMatchesPointValues(field, grid, values);
  values.resize(5);
  EXPECT_THROW(addCentresOnGrid(field, grid, changed, change, values), std::invalid_argument);
}

TEST(FieldOnGrid, CentresOutsideTheGridAndEmptyGrids) {
  std::mt19937 rng(3);
  const GaussianField field = test::makeRandomField(rng, 20, 0.005, 2.0, 20.0, 1e-8);
  RegularGrid grid;
  grid.origin_mm = Eigen::Vector3d(200.0, 0.0, 0.0);  // far from every centre: only b
  grid.cell_mm = 2.0;
  grid.counts = {3, 4, 5};
  std::vector<double> values;
  calcValuesOnGrid(field, grid, values);
  for (double v : values) EXPECT_EQ(v, field.getOffset());
  grid.counts = {0, 4, 5};
  calcValuesOnGrid(field, grid, values);
  EXPECT_TRUE(values.empty());
  grid.cell_mm = 0.0;
  EXPECT_THROW(calcValuesOnGrid(field, grid, values), std::invalid_argument);
}

}  // namespace
}  // namespace rbfmuscle
