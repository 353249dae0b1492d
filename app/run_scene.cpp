// One run of a scene: mesh, simulation, writers, renderer.
#include "run_scene.hpp"

#include <filesystem>

#include "output.hpp"
#include "plate_mesh.hpp"
#include "render_commands.hpp"

namespace brittle {

RunSummary run_scene(Scene scene, const std::vector<Observer*>& extra) {
  add_render_times_to_frames(scene);  // [render] times are frames too
  auto mesh = make_mesh(scene);
  Simulation sim(scene, *mesh);
  std::filesystem::create_directories(scene.output.directory);
  OutputWriters writers(sim);
  std::vector<Observer*> observers = writers.observers();
  const auto renderer = make_render_observer(scene);  // null without render.times
  if (renderer) observers.push_back(renderer.get());
  observers.insert(observers.end(), extra.begin(), extra.end());
  return sim.run(observers);
}

}  // namespace brittle
