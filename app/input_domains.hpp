#pragma once
// The physical domain of every numeric flag, in one table (docs/inputs.md prints the same
// table): a value outside it is refused at parse time, exit 2, naming the flag and the range.
// Scene, look and manifest keys have theirs where they are read (render/src/scene_file.cpp,
// looks/, batch/), with the same bounds where they mean the same thing.
#include <CLI/CLI.hpp>

namespace foldcast::app {

// Adds each table entry's check to the option it names, and to every option that takes a
// value a check that the value is not empty (CLI11 reads "" as 0 for a number).
void apply_input_domains(CLI::App& app);

}  // namespace foldcast::app
