// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkBlockModelSource
 * @brief   Closed CAD-like test models with small holes, bumps and cavities (for
 *          vtkHoleBumpRemoval), like the Fixture, Disk and Battery models of Ho 1999
 *
 * A plate of (2 * FeaturesX + 1) x (2 * FeaturesY + 1) unit cells:
 *  - PLATE_WITH_HOLES: a one-cell square through-hole at every odd cell (genus FeaturesX * FeaturesY);
 *  - PLATE_WITH_ROUND_HOLES: FeaturesX x FeaturesY unit tiles, each with a round hole of radius
 *    0.3 (Segments facets);
 *  - BUMPS / CAVITIES: a one-cell column higher / lower by 0.4 at every odd cell of a 1-thick plate;
 *  - MIXED: bumps, plus (when there is room) a cavity, a hole and a deeper cavity.
 * Subdivisions splits each cell into n x n quads. Output: triangles, outward normals, closed.
 */
#ifndef vtkBlockModelSource_h
#define vtkBlockModelSource_h

#include "SurfaceLODFiltersModule.h"
#include "vtkPolyDataAlgorithm.h"

class SURFACELODFILTERS_EXPORT vtkBlockModelSource : public vtkPolyDataAlgorithm
{
public:
  static vtkBlockModelSource* New();
  vtkTypeMacro(vtkBlockModelSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum Models
  {
    PLATE_WITH_HOLES = 0,
    PLATE_WITH_ROUND_HOLES = 1,
    BUMPS = 2,
    CAVITIES = 3,
    MIXED = 4
  };
  vtkSetClampMacro(Model, int, PLATE_WITH_HOLES, MIXED);
  vtkGetMacro(Model, int);
  void SetModelToPlateWithHoles() { this->SetModel(PLATE_WITH_HOLES); }
  void SetModelToPlateWithRoundHoles() { this->SetModel(PLATE_WITH_ROUND_HOLES); }
  void SetModelToBumps() { this->SetModel(BUMPS); }
  void SetModelToCavities() { this->SetModel(CAVITIES); }
  void SetModelToMixed() { this->SetModel(MIXED); }

  /// Features per row and column (default 3 x 3).
  vtkSetClampMacro(FeaturesX, int, 1, 1000);
  vtkGetMacro(FeaturesX, int);
  vtkSetClampMacro(FeaturesY, int, 1, 1000);
  vtkGetMacro(FeaturesY, int);
  /// Quads per cell side (default 2); facets of a round hole (default 16, a multiple of 4).
  vtkSetClampMacro(Subdivisions, int, 1, 100);
  vtkGetMacro(Subdivisions, int);
  vtkSetClampMacro(Segments, int, 8, 1024);
  vtkGetMacro(Segments, int);

protected:
  vtkBlockModelSource();
  ~vtkBlockModelSource() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Model = PLATE_WITH_HOLES;
  int FeaturesX = 3;
  int FeaturesY = 3;
  int Subdivisions = 2;
  int Segments = 16;

private:
  vtkBlockModelSource(const vtkBlockModelSource&) = delete;
  void operator=(const vtkBlockModelSource&) = delete;
};

#endif
