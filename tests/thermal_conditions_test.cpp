// Thermal boundary-condition files (thermal/thermal.h): what they accept, what they refuse and
// where (file:line), which surface takes which table, and the rows and results they make.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "expect_error.h"
#include "thermal/thermal.h"

namespace radiosity::thermal {
namespace {

using testing::expectInputError;

BoundaryConditions parse(const std::string& text) {
  return parseBoundaryConditions(text, "bc.toml");
}

// A mesh of one triangle per label, labelled as the OBJ reader labels them.
Mesh labelled(const std::vector<std::string>& labels) {
  Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.labelNames = labels;
  for (size_t l = 0; l < labels.size(); ++l) {
    mesh.triangles.push_back({0, 1, 2});
    mesh.sourceFace.push_back(static_cast<int64_t>(l));
    mesh.reflectance.push_back({0.5, 0.5, 0.5});
    mesh.emission.push_back({0, 0, 0});
    mesh.label.push_back(static_cast<int32_t>(l));
  }
  return mesh;
}

TEST(ThermalConditions, ReadsSurfacesAndADefaultInTheFilesOrder) {
  const BoundaryConditions c = parse(
      "# a furnace\n[surface.\"walls\"]\nemissivity = 0.3\nheat_flux = 0\n"
      "[surface.floor]\nemissivity = 1\ntemperature = 1000\n[default]\nemissivity = 0.5\n"
      "temperature = 300.5\n");
  ASSERT_EQ(c.surfaces.size(), 2u);
  EXPECT_EQ(c.surfaces[0].name, "walls");
  EXPECT_EQ(c.surfaces[0].line, 2);
  EXPECT_FALSE(c.surfaces[0].knowsTemperature());
  EXPECT_EQ(*c.surfaces[0].heatFlux, 0.0);
  EXPECT_EQ(c.surfaces[1].name, "floor");
  EXPECT_EQ(*c.surfaces[1].temperature, 1000.0);  // an integer is a number too
  ASSERT_TRUE(c.fallback.has_value());
  EXPECT_EQ(*c.fallback->temperature, 300.5);
}

// [surroundings]: black surroundings at a temperature, 0 K where the file gives none.
TEST(ThermalConditions, ReadsTheSurroundingsTemperature) {
  const std::string surface = "[default]\nemissivity = 0.5\ntemperature = 300\n";
  EXPECT_EQ(parse(surface).surroundingsTemperature, 0.0);
  EXPECT_EQ(parse(surface).surroundingsEmission(), 0.0);
  const BoundaryConditions c = parse(surface + "[surroundings]\ntemperature = 293\n");
  EXPECT_EQ(c.surroundingsTemperature, 293.0);
  EXPECT_EQ(c.surroundingsLine, 5);
  EXPECT_DOUBLE_EQ(c.surroundingsEmission(), kStefanBoltzmann * std::pow(293.0, 4));
  expectInputError([&] { parse(surface + "[surroundings]\ntemperature = -3\n"); },
                   {"bc.toml:5:", "[surroundings]", "below absolute zero"});
  expectInputError([&] { parse(surface + "[surroundings]\ntemperature = nan\n"); },
                   {"bc.toml:5:", "must be finite"});
  expectInputError([&] { parse(surface + "[surroundings]\ntemperature = 1e30\n"); },
                   {"bc.toml:5:", "emits more than the solver takes"});
  expectInputError([&] { parse(surface + "[surroundings]\ntemperature = 3\nemissivity = 1\n"); },
                   {"bc.toml:6:", "unknown key 'emissivity'", "black"});
  expectInputError([&] { parse(surface + "[surroundings]\n"); }, {"bc.toml:4:", "no temperature"});
  expectInputError([&] { parse("surroundings = 3\n" + surface); },
                   {"bc.toml:1:", "must be a table"});
}

TEST(ThermalConditions, RefusesWhatIsNotAConditionNamingFileAndLine) {
  const std::string head = "[surface.\"a\"]\n";
  expectInputError([&] { parse(head + "emissivity = 0.5\ntemprature = 3\n"); },
                   {"bc.toml:3:", "unknown key 'temprature'"});
  EXPECT_FALSE(parse(head + "temperature = 300\n").surfaces[0].emissivityGiven);  // the scene's
  for (const char* e : {"0", "-0.2"})
    expectInputError([&] { parse(head + "emissivity = " + e + "\ntemperature = 300\n"); },
                     {"bc.toml:2:", "below 1e-06"});
  expectInputError([&] { parse(head + "emissivity = 1.5\ntemperature = 300\n"); },
                   {"bc.toml:2:", "emissivity 1.5 is above 1"});
  expectInputError([&] { parse(head + "emissivity = nan\ntemperature = 300\n"); },
                   {"bc.toml:2:", "finite"});
  expectInputError([&] { parse(head + "emissivity = 0.5\ntemperature = 300\nheat_flux = 1\n"); },
                   {"bc.toml:1:", "both temperature and heat_flux"});
  expectInputError([&] { parse(head + "emissivity = 0.5\n"); },
                   {"bc.toml:1:", "neither temperature"});
  expectInputError([&] { parse(head + "emissivity = 0.5\ntemperature = -1\n"); },
                   {"bc.toml:3:", "below absolute zero"});
  expectInputError([&] { parse(head + "emissivity = 0.5\ntemperature = 1e30\n"); },
                   {"bc.toml:3:", "emits more than the solver takes"});
  expectInputError([&] { parse(head + "emissivity = 0.5\nheat_flux = inf\n"); },
                   {"bc.toml:3:", "finite"});
  expectInputError([&] { parse(head + "emissivity = \"high\"\ntemperature = 3\n"); },
                   {"bc.toml:2:", "must be a number"});
  expectInputError([&] { parse(head + "emissivity = true\ntemperature = 3\n"); },
                   {"bc.toml:2:", "must be a number"});
  expectInputError([&] { parse("[surfaces.\"a\"]\nemissivity = 1\ntemperature = 3\n"); },
                   {"bc.toml:1:", "unknown key 'surfaces'"});
  expectInputError([&] { parse("surface = 3\n"); }, {"bc.toml:1:", "[surface.\"NAME\"]"});
  expectInputError([&] { parse("[surface]\na = 3\n"); }, {"bc.toml:2:", "must be a table"});
  expectInputError([&] { parse("[surface.\"a\"\nemissivity = 1\n"); }, {"bc.toml:1:"});
  expectInputError([&] { parse("# nothing\n"); }, {"bc.toml", "nothing to solve"});
  expectInputError([] { readBoundaryConditions("/nonexistent/bc.toml"); },
                   {"/nonexistent/bc.toml"});
  expectInputError([] { readBoundaryConditions("/dev/null"); }, {"/dev/null"});
}

// What a refusal says is what the file says: an emissivity too small for the solver refused
// here (it used to be taken, and the run failed with exit 4 after the form factors), one just
// above 1 in enough digits to see why, a table given twice by its header as written.
TEST(ThermalConditions, RefusalsNameTheValueAndTheTableAsWritten) {
  const std::string head = "[surface.\"a\"]\n";
  expectInputError([&] { parse(head + "emissivity = 1e-17\ntemperature = 300\n"); },
                   {"bc.toml:2:", "emissivity 1e-17 is below 1e-06", "the least"});
  EXPECT_EQ(parse(head + "emissivity = 1e-6\ntemperature = 300\n").surfaces[0].emissivity, 1e-6);
  expectInputError([&] { parse(head + "emissivity = 1.0000001\ntemperature = 300\n"); },
                   {"bc.toml:2:", "emissivity 1.0000001 is above 1"});
  const auto twice = [&](const std::string& text, const std::vector<std::string>& mentions) {
    expectInputError([&] { parse(text); }, mentions);
    try {
      parse(text);
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find("roroof"), std::string::npos) << e.what();
    }
  };
  twice("[surface.\"roof\"]\nemissivity = 1\ntemperature = 300\n\n  [surface.\"roof\"] # again\n",
        {"bc.toml:5:", "table [surface.\"roof\"] is defined twice (first at line 1)"});
  twice("[surface.\"a]b\"]\nemissivity = 1\ntemperature = 3\n[surface.\"a]b\"]\n",
        {"bc.toml:4:", "[surface.\"a]b\"] is defined twice (first at line 1)"});
  twice("[default]\nemissivity = 1\ntemperature = 3\n[default]\n",
        {"bc.toml:4:", "[default] is defined twice"});
}

// A name that is one surface's material and another's group would apply to both without a
// word: refused, naming both and their whole labels. A name that is a material (or a group)
// throughout names all its surfaces.
TEST(ThermalConditions, ANameThatIsAMaterialAndAnotherSurfacesGroupIsRefused) {
  const std::string lid = "[surface.lid]\nemissivity = 1\ntemperature = 3\n";
  for (const char* material : {"lid (group box)", "lid"})
    expectInputError(
        [&] {
          matchSurfaces(labelled({material, "steel (group lid)"}), parse(lid));
        },
        {"bc.toml:1:", std::string("'") + material + "' by its material",
         "'steel (group lid)' by its group", "[surface.\"steel (group lid)\"]"});
  EXPECT_EQ(matchSurfaces(labelled({"lid (group a)", "lid (group b)"}), parse(lid)),
            (std::vector<int>{0, 0}));
  EXPECT_EQ(matchSurfaces(labelled({"steel (group lid)", "lid (group lid)"}), parse(lid)),
            (std::vector<int>{0, 0}));
  // Whole labels name each apart.
  EXPECT_EQ(matchSurfaces(labelled({"lid (group box)", "steel (group lid)"}),
                          parse("[surface.\"lid (group box)\"]\nemissivity = 1\ntemperature = 3\n"
                                "[surface.\"steel (group lid)\"]\nemissivity = 1\n"
                                "temperature = 3\n")),
            (std::vector<int>{0, 1}));
}

TEST(ThermalConditions, EachSurfaceTakesTheTableOfItsMaterialOrGroup) {
  const Mesh mesh = labelled({"white (group walls)", "white (group floor)", "lamp"});
  const BoundaryConditions c = parse(
      "[surface.\"walls\"]\nemissivity = 0.3\nheat_flux = 0\n[surface.lamp]\nemissivity = 0.9\n"
      "temperature = 2000\n[default]\nemissivity = 0.5\ntemperature = 300\n");
  const std::vector<int> of = matchSurfaces(mesh, c);
  EXPECT_EQ(of, (std::vector<int>{0, -1, 1}));  // floor: the default
  EXPECT_EQ(conditionOf(c, of, 1).name, "");
  // Both a material's table and a group's: refused, naming both.
  expectInputError(
      [&] {
        matchSurfaces(mesh, parse("[surface.white]\nemissivity = 1\ntemperature = 3\n"
                                  "[surface.walls]\nemissivity = 1\ntemperature = 3\n"
                                  "[default]\nemissivity = 1\ntemperature = 3\n"));
      },
      {"bc.toml:4:", "'white (group walls)'", "[surface.\"white\"] (line 1)"});
  // A table that names nothing, a surface without a condition, and no temperature anywhere.
  expectInputError(
      [&] {
        matchSurfaces(mesh, parse("[surface.wals]\nemissivity = 1\ntemperature = 3\n[default]\n"
                                  "emissivity = 1\ntemperature = 3\n"));
      },
      {"bc.toml:1:", "names no material or group", "'white (group walls)'"});
  expectInputError(
      [&] { matchSurfaces(mesh, parse("[surface.lamp]\nemissivity = 1\ntemperature = 3\n")); },
      {"bc.toml", "'white (group walls)' has no condition", "[surface.\"walls\"]"});
  expectInputError(
      [&] { matchSurfaces(mesh, parse("[default]\nemissivity = 1\nheat_flux = 5\n")); },
      {"bc.toml", "none a temperature", "singular"});
  // A scene without names: the default only.
  Mesh unnamed = labelled({"x"});
  unnamed.label.clear();
  unnamed.labelNames.clear();
  EXPECT_TRUE(
      matchSurfaces(unnamed, parse("[default]\nemissivity = 1\ntemperature = 3\n")).empty());
  expectInputError(
      [&] { matchSurfaces(unnamed, parse("[surface.x]\nemissivity = 1\ntemperature = 3\n")); },
      {"bc.toml:1:", "names no materials or groups"});
}

// "Küche" written decomposed (u and U+0308, NFD) names no surface of a scene that spells it
// composed (ü, NFC): the refusal says so with both spellings' code points, instead of listing
// a name that looks identical. A name merely unaccented, or otherwise accented, is not that.
TEST(ThermalConditions, ANameSpeltInOtherUnicodeCodePointsIsRefusedSayingSo) {
  const std::string composed =
                        "K\xC3\xBC"
                        "che",
                    decomposed =
                        "Ku\xCC\x88"
                        "che";
  const auto table = [](const std::string& name) {
    return "[surface.\"" + name +
           "\"]\nemissivity = 1\ntemperature = 3\n[default]\n"
           "emissivity = 1\ntemperature = 3\n";
  };
  const Mesh scene = labelled({composed + " (group kitchen)", "hall"});
  expectInputError([&] { matchSurfaces(scene, parse(table(decomposed))); },
                   {"bc.toml:1:", "names no material or group", "'Ku\\u0308che' (decomposed",
                    "the scene's 'K\\u00FCche' (composed", "other Unicode code points"});
  const Mesh nfdScene = labelled({decomposed, "hall"});
  expectInputError([&] { matchSurfaces(nfdScene, parse(table(composed))); },
                   {"'K\\u00FCche' (composed", "the scene's 'Ku\\u0308che' (decomposed"});
  for (const std::string& other : {std::string("Kuche"), std::string("Ka\xCC\x88"
                                                                     "che")}) {
    try {
      matchSurfaces(scene, parse(table(other)));
      ADD_FAILURE() << other << " matched";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).find("code points"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("its surfaces:"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(matchSurfaces(scene, parse(table(composed)))[0], 0);  // as the scene spells it
}

// A table without `emissivity` takes the scene's (a .vs3's surfaces state theirs): each surface
// its own, through a table of its own; where the scene states none, the table's line says so.
TEST(ThermalConditions, EmissivitiesTheSceneStatesServeTablesWithoutOne) {
  Mesh mesh = labelled({"hot", "cold", "wall"});
  mesh.labelEmissivity = {0.8, 0.5, std::nan("")};
  BoundaryConditions c = parse(
      "[surface.hot]\ntemperature = 1000\n[surface.wall]\nemissivity = 0.3\nheat_flux = 0\n"
      "[default]\ntemperature = 300\n");
  std::vector<int> of = matchSurfaces(mesh, c);
  resolveEmissivities(mesh, c, of);
  EXPECT_EQ(conditionOf(c, of, 0).emissivity, 0.8);
  EXPECT_EQ(*conditionOf(c, of, 0).temperature, 1000.0);
  EXPECT_EQ(conditionOf(c, of, 1).emissivity, 0.5);  // [default]'s temperature, its own ε
  EXPECT_EQ(*conditionOf(c, of, 1).temperature, 300.0);
  EXPECT_EQ(conditionOf(c, of, 1).name, "cold");
  EXPECT_EQ(conditionOf(c, of, 2).emissivity, 0.3);  // given: the file's
  applyConditions(mesh, c, of);
  EXPECT_NEAR(mesh.reflectance[0][0], 0.2, 1e-15);

  BoundaryConditions none = parse(
      "[surface.wall]\nheat_flux = 0\n[default]\nemissivity = 1\n"
      "temperature = 300\n");
  std::vector<int> ofNone = matchSurfaces(mesh, none);
  expectInputError([&] { resolveEmissivities(mesh, none, ofNone); },
                   {"bc.toml:1:", "no emissivity", "'wall'"});
  const Mesh plain = labelled({"wall"});
  BoundaryConditions fromObj = parse("[surface.wall]\ntemperature = 300\n");
  std::vector<int> ofObj = matchSurfaces(plain, fromObj);
  expectInputError([&] { resolveEmissivities(plain, fromObj, ofObj); },
                   {"bc.toml:1:", "no emissivity"});
}

TEST(ThermalConditions, KnownTemperatureEmitsAndReflectsKnownFluxIsAFluxRow) {
  Mesh mesh = labelled({"hot", "wall"});
  const BoundaryConditions c = parse(
      "[surface.hot]\nemissivity = 0.8\ntemperature = 1000\n[surface.wall]\nemissivity = 0.3\n"
      "heat_flux = -250\n");
  applyConditions(mesh, c, matchSurfaces(mesh, c));
  const double emitted = 0.8 * kStefanBoltzmann * 1e12;
  EXPECT_DOUBLE_EQ(mesh.reflectance[0][1], 1 - 0.8);
  EXPECT_DOUBLE_EQ(mesh.emission[0][2], emitted);
  EXPECT_EQ(mesh.reflectance[1], (Rgb{1, 1, 1}));
  EXPECT_EQ(mesh.emission[1], (Rgb{-250, -250, -250}));
  // After a solve: q = J − H; a known flux's temperature from σT⁴ = H + q/ε.
  const double h = 30000, j = emitted + 0.2 * h;
  const PatchHeat hot = patchHeat(c.surfaces[0], j, h);
  EXPECT_DOUBLE_EQ(hot.temperature, 1000);
  EXPECT_NEAR(hot.netHeatFlux, 0.8 * (kStefanBoltzmann * 1e12 - h), 1e-9 * h);
  const PatchHeat wall = patchHeat(c.surfaces[1], h - 250, h);
  EXPECT_NEAR(kStefanBoltzmann * std::pow(wall.temperature, 4), h - 250 / 0.3, 1e-9 * h);
  EXPECT_TRUE(std::isnan(patchHeat(c.surfaces[1], 0, 10).temperature));  // asks for too much
  // Errors: H's error moves a known temperature's flux by −ε of itself (a black one's too), a
  // known flux's σT⁴ by itself.
  const PatchHeatError e = patchHeatError(c.surfaces[0], hot, 2.0, -1.0);
  EXPECT_DOUBLE_EQ(e.netHeatFluxStderr, 0.8 * 2.0);
  EXPECT_DOUBLE_EQ(e.netHeatFlux, 0.8 * 1.0);
  const PatchHeatError w = patchHeatError(c.surfaces[1], wall, 3.0, 4.0);
  EXPECT_NEAR(w.temperature, 5.0 / (4 * kStefanBoltzmann * std::pow(wall.temperature, 3)), 1e-12);
  const SurfaceCondition black{"b", 1, 1.0, 500.0, std::nullopt};
  const PatchHeatError b = patchHeatError(black, patchHeat(black, 1, 1), 1.5, 2.0);
  EXPECT_DOUBLE_EQ(b.netHeatFluxStderr, 1.5);
  EXPECT_DOUBLE_EQ(b.netHeatFlux, -2.0);
}

}  // namespace
}  // namespace radiosity::thermal
