// Keeps PCL's console quiet while an object of this class lives. PCL prints
// routine outcomes that LiSTA handles itself (a tile without a plane, a
// keypoint without a frame, an ICP run short of correspondences) as errors
// on stderr, even under --quiet. PCL has only a process-wide level, so
// nested and concurrent holders share it: the first one lowers it, the last
// one restores what was there before.
#pragma once

#include <pcl/console/print.h>

namespace lista::pcl_convert {

class QuietPcl {
 public:
  QuietPcl();
  ~QuietPcl();
  QuietPcl(const QuietPcl&) = delete;
  QuietPcl& operator=(const QuietPcl&) = delete;
};

}  // namespace lista::pcl_convert
