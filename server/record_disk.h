#pragma once
/// The record directory's disk: a full one was silent (the server ran on and new sessions got
/// 0-byte records). Policy (docs/security.md, "Files and disks"): below the minimum free
/// space, creates are refused with the reason; running sessions go on (what a trainee feels
/// matters more than its record), their records stop growing, and each session's status counts
/// the events its record lost; every heartbeat carries the free space.
#include <cstdint>
#include <string>

#include "server/server_config.h"

namespace viscera::server {

/// Bytes an unprivileged writer may still use on the disk holding `dir`; -1 when unknown.
int64_t FreeBytes(const std::string& dir);

/// Why a create must be refused for its record ("" when it may go on, or nothing is recorded).
std::string RecordDiskProblem(const ServerConfig& config);

}  // namespace viscera::server
