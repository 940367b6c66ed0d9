// ROS 2 bags without a ROS 2 installation: a rosbag2 folder (metadata.yaml
// plus .db3 SQLite or .mcap storage files) read and written through the
// plain messages of lista_bag/messages.hpp. Messages must be CDR-encoded;
// compressed bags (compression_format set) are refused with what to do.
#pragma once

#include <lista_bag/messages.hpp>

#include <memory>
#include <string>

namespace lista::bag {

// A ROS 2 bag folder (metadata.yaml + .db3/.mcap files) or one .db3/.mcap file.
// Throws lista::Error naming the path when it is neither or is unreadable.
std::unique_ptr<Reader> open_ros2(const std::string& path);


enum class Ros2Storage { sqlite3, mcap };

// Creates `folder` (must not exist or be empty) with metadata.yaml and one
// storage file (<folder name>_0.db3 or .mcap; MCAP chunks are zstd). Both
// files appear under their final names only on close().
std::unique_ptr<Writer> create_ros2(const std::string& folder, Ros2Storage storage);

}  // namespace lista::bag
