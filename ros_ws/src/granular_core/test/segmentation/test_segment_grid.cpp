// ObjectSegmenter's grid (segment_grid.h): which points are candidates, their cells in
// row-major order, each cell's highest return, and the cell bits the links scan.
#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "segmentation/segment_grid.h"

namespace granular {
namespace {
using segmentation_detail::buildFrameGrid;
using segmentation_detail::CellBits;
using segmentation_detail::FrameGrid;
using segmentation_detail::PlaneGrid;

TEST(PlaneGridTest, CellsAreHalfOpenAndRowMajorAroundTheSensor) {
  const PlaneGrid grid(1.0, 10.0);
  EXPECT_EQ(grid.side, 20);  // 2 * 10 / 1 exactly: no extra column for rounding
  EXPECT_EQ(grid.cells(), 400u);
  EXPECT_EQ(*grid.cellOf(-10.0, -10.0), 0u);
  EXPECT_EQ(*grid.cellOf(5.5, 0.5), 10u * 20 + 15);
  EXPECT_EQ(*grid.cellOf(9.999, 9.999), 399u);
  EXPECT_FALSE(grid.cellOf(10.0, 0.0));
  EXPECT_FALSE(grid.cellOf(0.0, -10.001));
  EXPECT_DOUBLE_EQ(grid.centre(0), -9.5);
  EXPECT_DOUBLE_EQ(grid.centre(19), 9.5);
  EXPECT_EQ(PlaneGrid(0.15, 80.0).side, 1067);  // ceil(160 / 0.15)
}

TEST(CellBitsTest, VisitsExactlyTheSetCellsOfARangeInOrder) {
  // 150 columns: three words a row, ranges across word boundaries.
  const int side = 150;
  std::vector<std::uint64_t> words;
  CellBits bits(words, side);
  std::mt19937 random(3);
  std::uniform_int_distribution<int> cell(0, side * side - 1);
  std::set<int> set;
  for (int i = 0; i < 3000; ++i) {
    set.insert(cell(random));
  }
  for (const int c : set) {
    bits.set(static_cast<std::uint32_t>(c));
  }
  std::uniform_int_distribution<int> column(0, side - 1);
  for (int trial = 0; trial < 500; ++trial) {
    const int row = column(random);
    int first = column(random), last = column(random);
    if (trial % 2 == 0 && first > last) {
      std::swap(first, last);
    }
    std::vector<int> expected;
    for (int c = first; c <= last; ++c) {
      if (set.count(row * side + c) > 0) {
        expected.push_back(c);
      }
    }
    std::vector<int> visited;
    bits.forEachSet(row, first, last, [&](int c) { visited.push_back(c); });
    EXPECT_EQ(visited, expected) << "row " << row << " columns " << first << ".." << last;
  }
  for (const int c : set) {
    bits.clear(static_cast<std::uint32_t>(c));
  }
  for (const std::uint64_t word : words) {
    EXPECT_EQ(word, 0u);
  }
}

// A 20 x 20 grid of 1 m cells out to 10 m, and points each testing one rule.
class FrameGridTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config_.cell_size = 1.0;
    config_.min_range = 2.0;
    config_.max_range = 10.0;
    config_.max_height = 3.0;
    config_.link_min_top = 0.4;
    add(5.5f, 0.5f, 1.0f);    // 0: candidate, cell (row 10, col 15)
    add(-4.5f, -3.5f, 0.2f);  // 1: candidate, cell (6, 5)
    add(5.2f, 0.7f, 2.0f);    // 2: candidate, cell (10, 15)
    add(5.7f, 0.2f, 5.0f);    // 3: overhang over (10, 15)
    add(5.5f, 0.5f, 9.0f);    // 4: 8 m or higher: neither
    add(1.0f, 1.0f, 1.0f);    // 5: within min_range (the own vehicle)
    add(9.0f, 9.0f, 1.0f);    // 6: beyond max_range
    add(3.0f, 3.0f, 1.0f, true);  // 7: ground
    add(3.0f, -3.0f, NAN);    // 8: no height (a non-finite point)
    add(-4.2f, -3.9f, 0.3f);  // 9: candidate, cell (6, 5)
    add(-7.5f, 5.5f, 4.0f);   // 10: overhang over an empty cell
    add(0.5f, -6.5f, 0.5f);   // 11: candidate, cell (3, 10)
  }

  void add(float x, float y, float height, bool ground = false) {
    cloud_.push_back(PointXYZIT(x, y, height - 1.7f, 0, 0.0));
    ground_.heights.push_back(height);
    ground_.ground.push_back(ground);
  }

  ObjectSegmentationConfig config_;
  Cloud cloud_;
  GroundEstimate ground_;
};

TEST_F(FrameGridTest, CandidatesComeByCellInRowMajorOrderWithTheirCellsHighestReturn) {
  const PlaneGrid grid(config_.cell_size, config_.max_range);
  std::vector<std::int32_t> slot(grid.cells(), -1);
  std::vector<std::uint64_t> words;
  CellBits held(words, grid.side);
  const FrameGrid frame = buildFrameGrid(cloud_, ground_, config_, grid, slot, held);

  const std::vector<std::uint32_t> occupied = {3 * 20 + 10, 6 * 20 + 5, 10 * 20 + 15};
  EXPECT_EQ(frame.occupied, occupied);
  EXPECT_EQ(frame.start, (std::vector<std::uint32_t>{0, 1, 3, 5}));
  EXPECT_EQ(frame.by_cell, (std::vector<std::size_t>{11, 1, 9, 0, 2}));  // cloud order
  // Cell (10, 15)'s top is the overhang's 5 m; point 4 at 9 m counts nowhere.
  EXPECT_EQ(frame.top_of_cell, (std::vector<float>{0.5f, 0.3f, 5.0f}));
  EXPECT_EQ(frame.low, (std::vector<std::uint8_t>{0, 1, 0}));
  ASSERT_EQ(frame.centre.size(), 3u);
  EXPECT_EQ(frame.centre[0], Eigen::Vector2d(0.5, -6.5));
  EXPECT_EQ(frame.centre[1], Eigen::Vector2d(-4.5, -3.5));
  EXPECT_EQ(frame.centre[2], Eigen::Vector2d(5.5, 0.5));
  EXPECT_DOUBLE_EQ(frame.range[1], std::hypot(4.5, 3.5));

  // Each occupied cell's place is in its slot and its bit is set; nothing else.
  for (std::size_t cell = 0; cell < grid.cells(); ++cell) {
    const auto place = std::find(occupied.begin(), occupied.end(), cell);
    EXPECT_EQ(slot[cell], place == occupied.end() ? -1 : place - occupied.begin()) << cell;
  }
  std::vector<std::uint32_t> held_cells;
  for (int row = 0; row < grid.side; ++row) {
    held.forEachSet(row, 0, grid.side - 1, [&](int col) {
      held_cells.push_back(static_cast<std::uint32_t>(row * grid.side + col));
    });
  }
  EXPECT_EQ(held_cells, occupied);
}

TEST_F(FrameGridTest, AFrameWithoutCandidatesHasNoCells) {
  const PlaneGrid grid(config_.cell_size, config_.max_range);
  std::vector<std::int32_t> slot(grid.cells(), -1);
  std::vector<std::uint64_t> words;
  CellBits held(words, grid.side);
  config_.max_height = 0.1;  // every point above ground is now an overhang or too high
  const FrameGrid frame = buildFrameGrid(cloud_, ground_, config_, grid, slot, held);
  EXPECT_TRUE(frame.occupied.empty());
  EXPECT_EQ(frame.start, std::vector<std::uint32_t>{0});
  EXPECT_TRUE(frame.by_cell.empty());
  EXPECT_EQ(std::count(slot.begin(), slot.end(), -1), static_cast<long>(slot.size()));
}

}  // namespace
}  // namespace granular
