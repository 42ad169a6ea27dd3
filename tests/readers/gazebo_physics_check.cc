// Simulates an SDF world with Gazebo's own physics: ign-physics 5 (Gazebo Fortress) and its
// dartsim engine, the one gz-sim uses by default, built entity by entity as gz-sim's Physics
// system does: world, then per <model> a model, its links, and their collisions, mesh
// collisions attached as mesh shapes loaded by ign-common's MeshManager (dartsim cannot
// construct a mesh collision from SDF). Then a free sphere per drop point, and 3 s of steps.
//
// Usage: gazebo_physics_check WORLD.sdf RADIUS X,Y,Z [X,Y,Z ...]
//
// Prints, one per line:
//   model NAME collisions N       for every <model> of the world
//   mesh URI FROM-WORLD-FOLDER FROM-RESOURCE-PATH   each collision mesh URI resolved as gz-sim
//        does: against the SDF file's folder, and through GZ_SIM_RESOURCE_PATH (ign-common's
//        SystemPaths, from the current directory); "-" where not found
//   light NAME TYPE
//   ball I START X Y Z END X Y Z SPEED V
// and fails (non-zero) on an SDF error or a mesh that cannot be loaded.
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <ignition/common/Mesh.hh>
#include <ignition/math/eigen3/Conversions.hh>
#include <ignition/common/MeshManager.hh>
#include <ignition/common/SystemPaths.hh>
#include <ignition/physics/ConstructEmpty.hh>
#include <ignition/physics/FeatureList.hh>
#include <ignition/physics/ForwardStep.hh>
#include <ignition/physics/FrameSemantics.hh>
#include <ignition/physics/GetEntities.hh>
#include <ignition/physics/RequestEngine.hh>
#include <ignition/physics/mesh/MeshShape.hh>
#include <ignition/physics/sdf/ConstructLink.hh>
#include <ignition/physics/sdf/ConstructModel.hh>
#include <ignition/physics/sdf/ConstructWorld.hh>
#include <ignition/plugin/Loader.hh>
#include <sdf/sdf.hh>

namespace phys = ignition::physics;

using Features = phys::FeatureList<phys::sdf::ConstructSdfWorld, phys::sdf::ConstructSdfModel,
                                   phys::sdf::ConstructSdfLink, phys::mesh::AttachMeshShapeFeature,
                                   phys::GetEntities, phys::LinkFrameSemantics, phys::ForwardStep>;

static const char *kPlugin =
    "/usr/lib/x86_64-linux-gnu/ign-physics-5/engine-plugins/libignition-physics5-dartsim-plugin.so";

int main(int argc, char **argv) {
  if (argc < 4) {
    std::cerr << "usage: gazebo_physics_check WORLD.sdf RADIUS X,Y,Z [X,Y,Z ...]\n";
    return 2;
  }
  const std::filesystem::path sdfPath = std::filesystem::absolute(argv[1]);
  const double radius = std::atof(argv[2]);
  sdf::Root root;
  const sdf::Errors errors = root.Load(sdfPath.string());
  for (const auto &e : errors) std::cerr << "error: " << e << "\n";
  if (!errors.empty() || root.WorldCount() != 1) return 1;
  const sdf::World *world = root.WorldByIndex(0);

  const char *pluginPath = std::getenv("IGN_PHYSICS_DARTSIM_PLUGIN");
  ignition::plugin::Loader loader;
  if (loader.LoadLib(pluginPath ? pluginPath : kPlugin).empty()) {
    std::cerr << "cannot load the dartsim plugin " << (pluginPath ? pluginPath : kPlugin) << "\n";
    return 1;
  }
  auto plugin = loader.Instantiate("ignition::physics::dartsim::Plugin");
  auto engine = phys::RequestEngine3d<Features>::From(plugin);
  if (!engine) {
    std::cerr << "the dartsim plugin lacks a feature this checker needs\n";
    return 1;
  }

  // The world alone (gz-sim adds models one by one), with the file's gravity.
  sdf::World empty;
  empty.SetName(world->Name());
  empty.SetGravity(world->Gravity());
  auto physWorld = engine->ConstructWorld(empty);

  ignition::common::SystemPaths resources;
  resources.SetFilePathEnv("GZ_SIM_RESOURCE_PATH");
  const std::filesystem::path dir = sdfPath.parent_path();
  for (std::size_t i = 0; i < world->ModelCount(); ++i) {
    const sdf::Model *model = world->ModelByIndex(i);
    sdf::Model bare;
    bare.SetName(model->Name());
    bare.SetRawPose(model->RawPose());
    bare.SetStatic(model->Static());
    auto physModel = physWorld->ConstructModel(bare);
    std::size_t collisions = 0;
    for (std::size_t j = 0; j < model->LinkCount(); ++j) {
      const sdf::Link *link = model->LinkByIndex(j);
      sdf::Link bareLink;
      bareLink.SetName(link->Name());
      bareLink.SetRawPose(link->RawPose());
      auto physLink = physModel->ConstructLink(bareLink);
      for (std::size_t k = 0; k < link->CollisionCount(); ++k, ++collisions) {
        const sdf::Collision *c = link->CollisionByIndex(k);
        const sdf::Mesh *mesh = c->Geom() ? c->Geom()->MeshShape() : nullptr;
        if (!mesh) {
          std::cerr << model->Name() << ": collision " << c->Name() << " is not a mesh\n";
          return 1;
        }
        const auto local = dir / mesh->Uri();
        const std::string fromWorld =
            std::filesystem::is_regular_file(local) ? std::filesystem::canonical(local).string()
                                                    : "-";
        std::string fromResources = resources.FindFile(mesh->Uri(), false, false);
        if (!fromResources.empty() && std::filesystem::is_regular_file(fromResources)) {
          fromResources = std::filesystem::canonical(fromResources).string();
        } else {
          fromResources = "-";
        }
        std::cout << "mesh " << mesh->Uri() << " " << fromWorld << " " << fromResources << "\n";
        const ignition::common::Mesh *loaded =
            fromWorld == "-" ? nullptr : ignition::common::MeshManager::Instance()->Load(fromWorld);
        if (!loaded) {
          std::cerr << "MeshManager cannot load " << mesh->Uri() << "\n";
          return 1;
        }
        physLink->AttachMeshShape(c->Name(), *loaded, ignition::math::eigen3::convert(c->RawPose()),
                                  ignition::math::eigen3::convert(mesh->Scale()));
      }
    }
    std::cout << "model " << model->Name() << " collisions " << collisions << "\n";
  }
  for (std::size_t i = 0; i < world->LightCount(); ++i) {
    const sdf::Light *light = world->LightByIndex(i);
    const char *type = light->Type() == sdf::LightType::POINT         ? "point"
                       : light->Type() == sdf::LightType::DIRECTIONAL ? "directional"
                       : light->Type() == sdf::LightType::SPOT        ? "spot"
                                                                      : "other";
    std::cout << "light " << light->Name() << " " << type << "\n";
  }

  // A free sphere per drop point, made from SDF as gz-sim makes a spawned model.
  using ModelPtr = decltype(physWorld->ConstructModel(std::declval<sdf::Model>()));
  std::vector<ModelPtr> balls;
  std::vector<std::string> starts;
  for (int a = 3; a < argc; ++a) {
    std::string at = argv[a];
    for (char &ch : at) {
      if (ch == ',') ch = ' ';
    }
    std::ostringstream text;
    text << "<sdf version='1.9'><model name='ball_" << balls.size() << "'><pose>" << at
         << " 0 0 0</pose><link name='link'><inertial><mass>1</mass><inertia><ixx>0.016</ixx>"
            "<iyy>0.016</iyy><izz>0.016</izz></inertia></inertial><collision name='c'><geometry>"
            "<sphere><radius>"
         << radius << "</radius></sphere></geometry></collision></link></model></sdf>";
    sdf::Root ballRoot;
    const sdf::Errors ballErrors = ballRoot.LoadSdfString(text.str());
    if (!ballErrors.empty() || !ballRoot.Model()) {
      std::cerr << "bad drop point " << argv[a] << "\n";
      return 2;
    }
    balls.push_back(physWorld->ConstructModel(*ballRoot.Model()));
    starts.push_back(at);
  }

  phys::ForwardStep::Input input;
  phys::ForwardStep::State state;
  phys::ForwardStep::Output output;
  input.Get<std::chrono::steady_clock::duration>() =
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(0.001));
  for (int step = 0; step < 3000; ++step) physWorld->Step(output, state, input);

  for (std::size_t i = 0; i < balls.size(); ++i) {
    const auto frame = balls[i]->GetLink(0)->FrameDataRelativeToWorld();
    const Eigen::Vector3d p = frame.pose.translation();
    std::cout << "ball " << i << " start " << starts[i] << " end " << p.x() << " " << p.y()
              << " " << p.z() << " speed " << frame.linearVelocity.norm() << "\n";
  }
  return 0;
}
