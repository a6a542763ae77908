// NaN and Inf anywhere in the input: every fixture of tests/data that holds
// one (written by tests/data/make_test_data.py; JSON has no NaN literal, so
// JSON numbers carry 1e300 or 1e39, finite doubles that are +Inf as the
// floats they are stored in) fails the bake with kInvalidInput and a
// message naming the file and the element, and leaves the output directory
// as it was. Scenes built in code skip the loader: the baker's own boundary
// (flattening, light sources, solver) rejects them too.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include "stability_util.h"
#include "svit/baker/bake.h"

namespace svit::baker {
namespace {

using test::reportFigure;
using test::SceneBuilder;

bool contains(const std::string& haystack, const std::string& needle) {
  std::string h = haystack, n = needle;
  std::transform(h.begin(), h.end(), h.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  std::transform(n.begin(), n.end(), n.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return h.find(n) != std::string::npos;
}

struct BadFile {
  const char* file;
  const char* element;  // what the message must name besides the file
};

// Where the non-finite value sits, and the element the message names.
const BadFile kBadFiles[] = {
    {"nan_position.gltf", "mesh 'Quad' primitive 0 attribute POSITION vertex 2"},
    {"inf_normal.gltf", "attribute NORMAL vertex 1"},
    {"nan_texcoord.gltf", "attribute TEXCOORD_0 vertex 3"},
    {"inf_texcoord1.gltf", "attribute TEXCOORD_1 vertex 0"},
    {"overflow_base_color.gltf", "material 'Grey': baseColorFactor[1]"},
    {"overflow_emissive_factor.gltf", "material 'Glow': emissiveFactor[0]"},
    // The loader multiplies two finite doubles into an infinite float; the
    // baker's boundary catches it (named by mesh, triangle and material).
    {"overflow_emissive_strength.gltf",
     "mesh 'Quad' primitive 0 triangle 0 (material 'Glow'): emitted luminance"},
    {"overflow_translation.gltf", "node 'Quad': world transform"},
    {"overflow_scale.gltf", "node 'Quad': world transform"},
    {"overflow_matrix.gltf", "node 'Quad': world transform"},
    // Finite data, a finite regular transform, an infinite world corner.
    {"overflow_world_position.gltf", "node 'Quad' mesh 'Quad' primitive 0 triangle 0: corner"},
    {"nan_light_intensity.gltf", "light 0 'Lamp': intensity"},
    {"nonnumeric_light_intensity.gltf", "light 0 'Lamp': intensity"},
    // Light colour: finite double, infinite float; caught by the baker.
    {"overflow_light_color.gltf", "light 'Lamp': colour"},
    {"overflow_spot_angle.gltf", "light 0 'Spot': spot: outerConeAngle"},
    {"overflow_sun.level.json", "sun.illuminance_lux"},
    {"overflow_light_position.level.json", "lights[0].position[1]"},
    {"overflow_sky.level.json", "sky.zenith_luminance[1]"},
    {"overflow_camera.level.json", "camera_paths[0].keys[0].look_at[2]"},
};

TEST(NonFiniteInput, EveryFixtureFailsTheBakeNamingFileAndElementAndLeavesTheOutput) {
  test::StabilityTimer timer;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("svit_stability_input_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "out");
  // A previous bake's file (svit-bake replaces only a directory that holds
  // one): it must be left as it is.
  const std::filesystem::path previous = dir / "out" / "bake.svit";
  int rejected = 0;
  for (const BadFile& bad : kBadFiles) {
    SCOPED_TRACE(bad.file);
    {
      std::ofstream marker(previous);
      marker << "the previous bake\n";
    }
    BakeOptions options;
    options.level_path = std::string(SVIT_TEST_DATA_DIR) + "/" + bad.file;
    options.out_dir = (dir / "out").string();
    options.time_budget_s = 5;
    Expected<BakeResult> result = bakeLevel(options, {}, nullptr);
    ASSERT_FALSE(result.ok()) << "baked without error";
    const std::string& message = result.status().message();
    std::printf("%s -> %s\n", bad.file, message.c_str());
    EXPECT_EQ(result.status().code(), StatusCode::kInvalidInput) << message;
    EXPECT_TRUE(contains(message, bad.file)) << message;
    EXPECT_TRUE(contains(message, bad.element)) << message << "\n  wanted: " << bad.element;
    // Nothing touched: the previous output alone.
    std::vector<std::string> entries;
    for (const auto& entry : std::filesystem::directory_iterator(dir / "out")) {
      entries.push_back(entry.path().filename().string());
    }
    EXPECT_EQ(entries, std::vector<std::string>{"bake.svit"});
    std::ifstream marker(previous);
    std::string line;
    std::getline(marker, line);
    EXPECT_EQ(line, "the previous bake");
    rejected += result.status().code() == StatusCode::kInvalidInput ? 1 : 0;
  }
  std::filesystem::remove_all(dir);
  reportFigure("fixtures rejected with a named element", rejected);
  reportFigure("fixtures", double(std::size(kBadFiles)));
}

// ---------------------------------------------------------------------------
// Scenes built in code (what a tool or a game hands the baker directly).

// A closed 2 m room with a lamp; `spoil` puts one non-finite value in it.
Status bakeBoundary(const std::function<void(Scene&)>& spoil) {
  SceneBuilder b;
  const int grey = b.material({0.5f, 0.5f, 0.5f});
  b.addRoom("room", {0, 0, 0}, {2, 2, 2}, grey);
  b.addPointLight({1, 1, 1}, 10.0f);
  Scene scene = b.scene();
  scene.source_path = "code.gltf";
  spoil(scene);
  Expected<BakeGeometry> geometry = flattenStaticGeometry(scene);
  if (!geometry.ok()) return geometry.status();
  Expected<std::unique_ptr<RayCaster>> caster = makeEmbreeCaster(*geometry);
  if (!caster.ok()) return caster.status();
  Expected<std::unique_ptr<RadiositySolver>> solver =
      RadiositySolver::create(scene, *geometry, **caster, RadiositySettings{});
  return solver.ok() ? Status() : solver.status();
}

TEST(NonFiniteInput, ScenesBuiltInCodeAreRejectedAtTheBakersBoundary) {
  test::StabilityTimer timer;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  struct Case {
    const char* what;
    std::function<void(Scene&)> spoil;
    const char* element;
  };
  const std::vector<Case> cases = {
      {"NaN position", [&](Scene& s) { s.meshes[2].positions[1].y = nan; },
       "mesh 'room -x' primitive 0 triangle 0: corner 1"},
      {"Inf world transform", [&](Scene& s) { s.instances[3].world_from_object.m[12] = inf; },
       "mesh 'room +x'"},
      {"NaN albedo", [&](Scene& s) { s.meshes[0].triangle_albedo[1].g = nan; },
       "mesh 'room floor' primitive 0 triangle 1 (material 'material 0'): albedo"},
      {"Inf emission", [&](Scene& s) { s.meshes[1].triangle_emission[0].r = inf; },
       "mesh 'room ceiling' primitive 0 triangle 0 (material 'material 0'): emitted luminance"},
      {"NaN light position", [&](Scene& s) { s.lights[0].position.x = nan; },
       "light 'point 0': position"},
      {"Inf light intensity", [&](Scene& s) { s.lights[0].intensity = inf; },
       "light 'point 0': intensity"},
      {"NaN sun direction",
       [&](Scene& s) {
         s.sun.enabled = true;
         s.sun.illuminance_lux = 1000;
         s.sun.direction_to_sun.z = nan;
       },
       "sun: direction"},
      {"Inf sky luminance",
       [&](Scene& s) {
         s.sky.model = SkyModel::kUniform;
         s.sky.zenith_luminance = {1, inf, 1};
       },
       "sky: a luminance"},
  };
  int rejected = 0;
  for (const Case& c : cases) {
    const Status status = bakeBoundary(c.spoil);
    std::printf("%s -> %s\n", c.what, status.message().c_str());
    EXPECT_EQ(status.code(), StatusCode::kInvalidInput) << c.what << ": " << status.message();
    EXPECT_TRUE(contains(status.message(), "code.gltf")) << c.what << ": " << status.message();
    EXPECT_TRUE(contains(status.message(), c.element))
        << c.what << ": " << status.message() << "\n  wanted: " << c.element;
    rejected += status.code() == StatusCode::kInvalidInput ? 1 : 0;
  }
  reportFigure("cases rejected with a named element", rejected);
  reportFigure("cases", double(cases.size()));
}

}  // namespace
}  // namespace svit::baker
