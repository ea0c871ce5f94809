#include "job/InputLoading.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "Error.h"
#include "domain/BrepSolid.h"
#include "domain/LabeledImage.h"
#include "domain/NrrdReader.h"
#include "domain/Sphere.h"
#include "domain/TriangleSurface.h"

#include <TopExp_Explorer.hxx>

namespace oraclemesh {

namespace {

// One job input as oracle entries (a B-rep file with several solids gives one entry per
// solid), with what kind of input each entry is and the warnings of loading it.
struct LoadedInput {
  std::vector<OracleEntry> entries;
  std::vector<std::string> kinds;  // per entry: "B-rep solid", "triangle surface", ...
  std::vector<std::string> warnings;
  double declared_uncertainty = 0;  // a STEP file's (BrepSolid::Loaded)
};

LoadedInput loadInput(const InputSpec& in, const RunControl& control, double progress) {
  LoadedInput loaded;
  auto add = [&](SourcePtr source, int material, const std::string& kind) {
    loaded.entries.push_back({std::move(source), in.role, material});
    loaded.kinds.push_back(kind);
  };
  const bool surfaceFile = in.kind == InputSpec::Kind::File && [&] {
    std::string ext = std::filesystem::path(in.file).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext == ".stl" || ext == ".obj" || ext == ".off";
  }();
  if (in.kind == InputSpec::Kind::Image) {
    // One entry per mapped label. The regions of one image are disjoint, so their order among
    // themselves does not matter; together they take the image's place in the priority list.
    const auto image = readNrrdLabels(in.image, in.name);
    for (auto& [region, material] : makeImageRegions(image, in.image_materials, in.name))
      add(region, material, "image region");
  } else if (in.kind == InputSpec::Kind::Sphere) {
    add(std::make_shared<Sphere>(in.center, in.radius, in.name), in.material, "sphere");
  } else if (in.kind == InputSpec::Kind::Surface) {
    add(TriangleSurface::fromTriangles(in.surface_points, in.surface_triangles, in.name), in.material,
        "triangle surface");
  } else if (surfaceFile) {
    add(TriangleSurface::fromFile(in.file, in.name), in.material, "triangle surface");
  } else {
    const auto grouping = in.solids_together ? BrepSolid::Grouping::Together : BrepSolid::Grouping::Separate;
    // In a helper process: OpenCASCADE may crash or hang on a damaged file.
    BrepSolid::Loaded brep =
        in.kind == InputSpec::Kind::File
            ? BrepSolid::loadFileIsolated(in.file, in.name, grouping, control, progress)
            : BrepSolid::loadBrepTextIsolated(in.brep_text, in.name, grouping, control, progress);
    if (!in.solid_materials.empty() && in.solid_materials.size() != brep.solids.size())
      throw InputError("input '" + in.name + "'" + (in.file.empty() ? "" : " (file '" + in.file + "')") + " has " +
                       std::to_string(brep.solids.size()) + " solid" + (brep.solids.size() == 1 ? "" : "s") +
                       " but 'materials' lists " + std::to_string(in.solid_materials.size()) +
                       ": give one material per solid, in file order");
    for (size_t i = 0; i < brep.solids.size(); ++i) {
      int solids = 0;
      for (TopExp_Explorer ex(brep.solids[i]->shape(), TopAbs_SOLID); ex.More(); ex.Next()) ++solids;
      add(brep.solids[i], in.solid_materials.empty() ? in.material : in.solid_materials[i],
          solids == 1 ? "B-rep solid" : "B-rep compound (" + std::to_string(solids) + " solids)");
    }
    loaded.warnings = std::move(brep.warnings);
    loaded.declared_uncertainty = brep.declared_uncertainty;
  }
  return loaded;
}

}  // namespace

LoadedInputs loadInputs(const JobSpec& job, const RunControl& control) {
  LoadedInputs all;
  for (size_t i = 0; i < job.inputs.size(); ++i) {
    const InputSpec& in = job.inputs[i];
    LoadedInput loaded = loadInput(in, control, double(i) / job.inputs.size());
    for (size_t k = 0; k < loaded.entries.size(); ++k) {
      all.entries.push_back(std::move(loaded.entries[k]));
      all.kinds.push_back(loaded.kinds[k]);
      all.inputs.push_back(in.name);
    }
    for (std::string& w : loaded.warnings) all.warnings.push_back(std::move(w));
    if (loaded.declared_uncertainty > all.declared_uncertainty) {
      all.declared_uncertainty = loaded.declared_uncertainty;
      all.declared_uncertainty_by = in.name;
    }
    control.report("load", double(i + 1) / job.inputs.size());
    control.checkpoint();
  }
  return all;
}

std::vector<InputReport> describeInputs(const HierarchicalOracle& oracle, const LoadedInputs& loaded) {
  std::vector<InputReport> inputs;
  for (size_t i = 0; i < oracle.entries().size(); ++i) {
    const OracleEntry& e = oracle.entries()[i];
    inputs.push_back({e.source->name(), loaded.inputs[i], loaded.kinds[i], e.role, e.material, e.source->volume()});
  }
  return inputs;
}

}  // namespace oraclemesh
