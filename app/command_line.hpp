// The shape every brittle command shares: named options plus repeatable positional arguments.
#pragma once

#include <string>
#include <vector>

#include <boost/program_options.hpp>

namespace brittle {

/// Parses `args` against `options`; bare arguments go to the repeatable option `positional`
/// (none when null). Unknown options throw. The caller checks --help, then calls notify().
inline boost::program_options::variables_map parse_command_line(
    const std::vector<std::string>& args, const boost::program_options::options_description& options,
    const char* positional) {
  namespace po = boost::program_options;
  po::positional_options_description bare;
  if (positional) bare.add(positional, -1);
  po::variables_map vm;
  po::store(po::command_line_parser(args).options(options).positional(bare).run(), vm);
  return vm;
}

}  // namespace brittle
