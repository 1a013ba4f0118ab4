// Sizes of memory and files as people write them: 512M, 4G, 1.5GiB, 1000000.
#pragma once

#include <cstdint>
#include <string>

namespace rtm {

/// Parses a byte count: a number, optionally followed by K, M, G or T (powers of 1024; KB, MiB
/// and the like mean the same). Throws std::invalid_argument naming the text if it is not one,
/// or if it is zero or past 2^60 bytes.
uint64_t parse_byte_size(const std::string& text);
/// "1.5 GiB", "300 KiB", "12 bytes".
std::string format_bytes(double bytes);

}  // namespace rtm
