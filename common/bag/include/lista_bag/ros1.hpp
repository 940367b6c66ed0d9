// ROS 1 .bag files, read and written with Debian's rosbag_storage.
#pragma once

#include <lista_bag/messages.hpp>

namespace lista::bag {

// One or more .bag files read as one stream (messages merged in time order).
std::unique_ptr<Reader> open_ros1(const std::vector<std::string>& bag_files);

// Writes one .bag file (LZ4-compressed chunks when `compress`).
std::unique_ptr<Writer> create_ros1(const std::string& bag_file, bool compress = false);

}  // namespace lista::bag
