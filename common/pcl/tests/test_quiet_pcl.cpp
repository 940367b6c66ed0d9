#include <lista_pcl/quiet.hpp>

#include <gtest/gtest.h>

#include <memory>

using lista::pcl_convert::QuietPcl;

// Holders overlap as stages run side by side: the level stays lowered until
// the last one goes, then is what it was before the first came.
TEST(QuietPcl, OverlappingHoldersRestoreTheLevelOnlyWhenTheLastGoes) {
  pcl::console::setVerbosityLevel(pcl::console::L_WARN);
  auto first = std::make_unique<QuietPcl>();
  EXPECT_EQ(pcl::console::getVerbosityLevel(), pcl::console::L_ALWAYS);
  auto second = std::make_unique<QuietPcl>();
  first.reset();  // not in the order they came
  EXPECT_EQ(pcl::console::getVerbosityLevel(), pcl::console::L_ALWAYS);
  second.reset();
  EXPECT_EQ(pcl::console::getVerbosityLevel(), pcl::console::L_WARN);
}
