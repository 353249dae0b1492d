// The rendering side of the command line: PNG frames during a run ([render] keys), `brittle
// render` (frames from a stored time series) and `brittle figure` (the paper's Figs. 7-10).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "scene.hpp"
#include "simulation.hpp"

namespace brittle {

/// The observer that writes <render.directory or output.directory/render>/<field>_<t>us.png at
/// each render time; null when render.times is empty.
std::unique_ptr<Observer> make_render_observer(const Scene& scene);

/// `brittle render RUN.pvd [SCENE.ini ...] [--times ...] [--field ...] [--set ...] [--out DIR]`
int render_command(const std::vector<std::string>& args);

/// `brittle figure SCENE.ini [MORE.ini ...] [--set ...] [--runs DIR] [--out DIR] [--reuse]`
int figure_command(const std::vector<std::string>& args);

}  // namespace brittle
