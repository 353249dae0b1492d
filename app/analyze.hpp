// `brittle analyze RUN_DIR`: the crack pattern of a finished (or stopped) fracture run again,
// from its events.csv, e.g. with another minimum branch length (docs/crack_pattern.md).
#pragma once

#include <string>
#include <vector>

namespace brittle {

/// `brittle analyze RUN_DIR [--min-branch-length L]`: rewrites RUN_DIR/branches.csv and
/// pattern.json from RUN_DIR/events.csv and the tracker settings in pattern.json; prints the
/// branches. 0 on success; bad input throws brittle::Error (exit 2).
int analyze_command(const std::vector<std::string>& args);

}  // namespace brittle
