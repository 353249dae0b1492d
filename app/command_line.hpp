// The shape every brittle command shares: named options plus repeatable positional arguments,
// and one form of `--help` (docs/cli.md).
#pragma once

#include <iostream>
#include <string>
#include <vector>

#include <boost/program_options.hpp>

namespace brittle {

/// Parses `args` against `options`; bare arguments go to the repeatable option `positional`
/// (none when null), declared in `hidden` so that --help does not list it. Unknown options
/// throw. The caller checks --help, then calls notify().
inline boost::program_options::variables_map parse_command_line(
    const std::vector<std::string>& args, const boost::program_options::options_description& options,
    const boost::program_options::options_description& hidden, const char* positional) {
  namespace po = boost::program_options;
  po::options_description all;
  all.add(options).add(hidden);
  po::positional_options_description bare;
  if (positional) bare.add(positional, -1);
  po::variables_map vm;
  po::store(po::command_line_parser(args).options(all).positional(bare).run(), vm);
  return vm;
}

/// A command without positional arguments.
inline boost::program_options::variables_map parse_command_line(
    const std::vector<std::string>& args, const boost::program_options::options_description& options) {
  return parse_command_line(args, options, boost::program_options::options_description(), nullptr);
}

/// `brittle COMMAND --help`: the command's usage line, what it does (and what its --out is),
/// then its options. Nothing of the other commands, nothing internal.
/// `about` is wrapped at 80 columns.
void print_command_help(std::ostream& out, const std::string& usage, const std::string& about,
                        const boost::program_options::options_description& options);

/// The word of a yes/no option (`--frames no`): yes/true/on/1 or no/false/off/0, any case;
/// throws brittle::Error naming the option otherwise.
bool parse_switch(const std::string& option, const std::string& word);

/// `--out` is a directory for every command (docs/cli.md): a value that names a file of a
/// picture or table (FIG.png, .csv, .json, .vtu) is refused, naming the file the command writes
/// there instead.
void check_out_directory(const std::string& command, const std::string& out,
                         const std::string& written);

}  // namespace brittle
