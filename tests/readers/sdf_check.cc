// Loads an SDF world with libsdformat (what gz-sim parses worlds with), fails on any error,
// and prints what it found: counts, then one line per mesh with its path resolved against
// the SDF file's folder (and whether that file exists), and each collision's friction.
#include <filesystem>
#include <iostream>
#include <string>

#include <sdf/sdf.hh>

int main(int argc, char **argv) {
  if (argc != 2) {
    std::cerr << "usage: sdf_check WORLD.sdf\n";
    return 2;
  }
  sdf::Root root;
  sdf::Errors errors = root.Load(argv[1]);
  for (const auto &e : errors) {
    std::cerr << "error: " << e << "\n";
  }
  if (!errors.empty() || root.WorldCount() != 1) {
    std::cerr << errors.size() << " errors, " << root.WorldCount() << " worlds\n";
    return 1;
  }
  const std::filesystem::path dir = std::filesystem::path(argv[1]).parent_path();
  const sdf::World *world = root.WorldByIndex(0);
  std::size_t links = 0, visuals = 0, collisions = 0, missing = 0, points = 0;
  auto mesh = [&](const char *what, const sdf::Geometry *g) {
    const sdf::Mesh *m = g ? g->MeshShape() : nullptr;
    if (!m) {
      std::cout << what << " not-a-mesh\n";
      ++missing;
      return;
    }
    const auto path = dir / m->Uri();
    const bool exists = std::filesystem::is_regular_file(path);
    missing += exists ? 0 : 1;
    std::cout << what << " " << std::filesystem::weakly_canonical(path).string()
              << (exists ? "" : " MISSING") << "\n";
  };
  for (std::size_t i = 0; i < world->ModelCount(); ++i) {
    const sdf::Model *model = world->ModelByIndex(i);
    if (!model->Static()) {
      std::cout << "dynamic-model " << model->Name() << "\n";
    }
    for (std::size_t j = 0; j < model->LinkCount(); ++j, ++links) {
      const sdf::Link *link = model->LinkByIndex(j);
      for (std::size_t k = 0; k < link->VisualCount(); ++k, ++visuals) {
        mesh("visual", link->VisualByIndex(k)->Geom());
      }
      for (std::size_t k = 0; k < link->CollisionCount(); ++k, ++collisions) {
        const sdf::Collision *c = link->CollisionByIndex(k);
        mesh("collision", c->Geom());
        // The ODE sliding friction as libsdformat parsed it (sdformat 12 has no typed
        // accessor): "friction MU COLLISION MODEL"; "friction default" without a <surface>.
        sdf::ElementPtr e = c->Element();
        for (const char *n : {"surface", "friction", "ode"}) {
          e = e && e->HasElement(n) ? e->GetElement(n) : nullptr;
        }
        std::cout << "friction ";
        if (e && e->HasElement("mu")) {
          std::cout << e->Get<double>("mu");
        } else {
          std::cout << "default";
        }
        std::cout << " " << c->Name() << " " << model->Name() << "\n";
      }
    }
  }
  for (std::size_t i = 0; i < world->LightCount(); ++i) {
    if (world->LightByIndex(i)->Type() == sdf::LightType::POINT) {
      ++points;
    }
  }
  std::cout << "models " << world->ModelCount() << "\nlinks " << links << "\nvisuals "
            << visuals << "\ncollisions " << collisions << "\nlights " << world->LightCount()
            << "\npoint-lights " << points << "\nmissing " << missing << "\n";
  return 0;
}
