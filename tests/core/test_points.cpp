// PointSet's optional channels (intensity, label, changed_against) follow
// the points through select, append and push_back_from, so a filter or a
// segmenter that only picks points keeps them; a set that lacks a channel
// makes the combination drop it rather than misalign it.
#include <lista/error.hpp>
#include <lista/points.hpp>

#include <gtest/gtest.h>

using namespace lista;

namespace {

PointSet change_points(std::vector<uint8_t> bits) {
  PointSet s;
  for (size_t i = 0; i < bits.size(); ++i) {
    s.xyz.emplace_back(float(i), 0.0f, 0.0f);
    s.label.push_back(uint32_t(10 + i));
    s.scan.push_back(0);
    s.index.push_back(uint32_t(i));
  }
  s.changed_against = std::move(bits);
  return s;
}

}  // namespace

TEST(PointSet, ChangedAgainstFollowsSelectAppendAndPushBack) {
  const PointSet s = change_points({changed_against_previous, changed_against_next, changed_against_either});
  s.check_consistent();
  const PointSet picked = s.select({2, 0});
  EXPECT_EQ(picked.changed_against, (std::vector<uint8_t>{changed_against_either, changed_against_previous}));
  EXPECT_EQ(picked.label, (std::vector<uint32_t>{12, 10}));

  PointSet joined = picked;
  joined.append(s.select({1}));
  EXPECT_EQ(joined.changed_against.size(), 3u);
  EXPECT_EQ(joined.changed_against.back(), changed_against_next);

  PointSet one;
  one.push_back_from(s, 1);
  EXPECT_EQ(one.changed_against, (std::vector<uint8_t>{changed_against_next}));
  joined.check_consistent();
}

TEST(PointSet, ChangedAgainstOfAllPointsTogether) {
  EXPECT_EQ(change_points({changed_against_previous, changed_against_previous}).changed_against_all(),
            changed_against_previous);
  EXPECT_EQ(change_points({changed_against_previous, changed_against_next}).changed_against_all(),
            changed_against_either);
  PointSet no_channel = change_points({1, 2});
  no_channel.changed_against.clear();
  EXPECT_EQ(no_channel.changed_against_all(), changed_against_either) << "not known: either neighbour";
}

TEST(PointSet, ASetWithoutTheChannelDropsItInsteadOfMisaligningIt) {
  PointSet with = change_points({changed_against_next, changed_against_next});
  PointSet without = change_points({1});
  without.changed_against.clear();
  with.append(without);
  EXPECT_TRUE(with.changed_against.empty());
  with.check_consistent();

  PointSet bad = change_points({1, 2});
  bad.changed_against.pop_back();
  EXPECT_THROW(bad.check_consistent(), Error);
}
