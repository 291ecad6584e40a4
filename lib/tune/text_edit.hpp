// Edits of a YAML config file as text, so that a proposed change keeps the file's comments and
// layout and shows as a small diff: the value of a key found by its path of block-map keys
// (`velocity_pid` > `surge`), either a block scalar (`turn_rate: 0.7  # comment`) or a key
// inside a one-line flow map (`surge: {k_drag: 77.5, ki: 60}`). Lines are the file's, without
// newlines.
#pragma once

#include <string>
#include <vector>

namespace tiller::tune {

std::vector<std::string> split_lines(const std::string& text);
std::string join_lines(const std::vector<std::string>& lines);

// The line index of the block key at `path` (each key a child of the one before, by
// indentation); -1 when absent.
int find_key_line(const std::vector<std::string>& lines, const std::vector<std::string>& path);

// Sets the value of path's last key (a block scalar or a flow sequence on its line) to `value`
// text, keeping a trailing comment; or, with `flow_key`, the value of that key inside the
// one-line flow map at `path`. Throws std::runtime_error naming the path when not found.
void set_value(std::vector<std::string>& lines, const std::vector<std::string>& path,
               const std::string& value, const std::string& flow_key = "");

// A unified diff (3 lines of context) of two versions of a file with the same number of lines
// (set_value changes no line count), paths a/`name` and b/`name`; empty when equal.
std::string unified_diff(const std::string& name, const std::vector<std::string>& before,
                         const std::vector<std::string>& after);

// A number as a config value: up to 4 significant digits, no exponent for 1e-3..1e6.
std::string format_number(double v);

}  // namespace tiller::tune
