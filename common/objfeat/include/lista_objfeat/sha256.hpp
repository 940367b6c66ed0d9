// SHA-256 (FIPS 180-4) of a byte buffer or a file, as lowercase hex. Used to
// verify shipped model weights against their recorded checksum.
#pragma once

#include <string>

namespace lista::objfeat {

std::string sha256_hex(const std::string& bytes);
// Throws lista::Error if the file cannot be read.
std::string sha256_file(const std::string& path);

}  // namespace lista::objfeat
