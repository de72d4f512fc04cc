// SPDX-License-Identifier: BSD-3-Clause
// The simplification methods the `surfacelod` tool can run: one registry, one entry per method.
#ifndef surfacelodMethods_h
#define surfacelodMethods_h

#include "vtkPolyDataAlgorithm.h"
#include "vtkSmartPointer.h"

#include <string>
#include <vector>

namespace slodcli
{
// What the user asked for; exactly one of TargetTriangles (> 0) or TargetReduction (>= 0) is set.
struct MethodSettings
{
  vtkIdType TargetTriangles = 0;
  double TargetReduction = -1.0; // fraction of the input triangles removed
  bool HasMaximumError = false;
  double MaximumError = 0.0; // absolute distance, in the mesh's units
  vtkIdType InputTriangles = 0;
  double Level = -1.0; // hierarchy level (i + t) instead of a target, for methods that have levels
  double FeatureSize = -1.0; // --feature-size (absolute, mesh units) for methods that remove features; < 0: not given

  // The target as a reduction fraction (for filters that only take that).
  double ReductionFraction() const;
};

// Whether `output` (of a method run with `settings`) reached its target: the filter's own
// "TargetReached" field data when it has it, else output triangles <= the count target.
bool TargetReached(vtkPolyData* output, const MethodSettings& settings);
// The same from figures: `reported` is the filter's "TargetReached" (1 or 0), -1 when it has none.
bool TargetReached(vtkIdType outputTriangles, int reported, const MethodSettings& settings);
// The filter's "TargetReached" field data of `output`: 1 or 0, -1 when it has none.
int ReportedTargetReached(vtkPolyData* output);

// A parameter of a method's filter that `--set Name=Value` may change (see Methods.cxx).
enum class ParameterType
{
  Bool,
  Int,
  Double
};

struct Parameter
{
  const char* Name; // the filter's property: Set<Name> / Get<Name>
  ParameterType Type;
  double (*Get)(vtkPolyDataAlgorithm* filter);
  void (*Set)(vtkPolyDataAlgorithm* filter, double value);
};

// A parsed `--set Name=Value`.
struct ParameterAssignment
{
  const Parameter* Target;
  double Value;
};

struct Method
{
  const char* Name;
  const char* Description;
  bool SupportsMaximumError;
  // A configured filter; the caller sets the input and calls Update().
  vtkSmartPointer<vtkPolyDataAlgorithm> (*Create)(const MethodSettings&);
  // What --set may change; the target and error bound have their own options.
  std::vector<Parameter> Parameters;
  bool SupportsLevel = false; // accepts --level (a level of a hierarchy) instead of a target
  // Run by `demo` and `bench` when no --methods is given. Off for methods whose time grows with the
  // accuracy asked (a bound-driven target search on a 1M-triangle surface takes many minutes).
  bool InDefaultRuns = true;
  // False for VTK's filters: they take their input as it is (vtkQuadricDecimation crashes on a
  // triangle with a repeated vertex), so the tool gives them the input SurfaceLOD's filters prepare.
  bool PreparesItsInput = true;
  // False for methods that remove features instead of reaching a triangle count (no -t/-r needed).
  bool NeedsTarget = true;
  // Its filter has a Controller and keeps the seams of distributed pieces: `mpiexec -n N surfacelod
  // simplify` may run it on N pieces (Distributed.h).
  bool SimplifiesPieces = false;
};

const std::vector<Method>& Methods();
// The method's filter configured by `settings`, then by `assignments` (which may override the tool's
// own choices, e.g. --set PreserveTopology=0 for vtk-decimate-pro).
vtkSmartPointer<vtkPolyDataAlgorithm> CreateFilter(
  const Method& method, const MethodSettings& settings, const std::vector<ParameterAssignment>& assignments);
// Parses "Name=Value" texts against the method's parameters. Throws CliError(ExitUsage) naming an
// unknown parameter, a value of the wrong type or one the filter clamps (out of its range).
std::vector<ParameterAssignment> ParseAssignments(const Method& method, const std::vector<std::string>& texts);
// A parameter's value as the tool's filter has it before any --set: "true", "3", "0.25".
std::string ParameterDefault(const Method& method, const Parameter& parameter);
const char* ParameterTypeName(ParameterType type);
const Method* FindMethod(const std::string& name); // nullptr when unknown
std::string MethodNames(const std::string& separator = ", ");

// The baseline that speed-ups are measured against.
constexpr const char* BaselineMethod = "vtk-quadric-decimation";
} // namespace slodcli

#endif
