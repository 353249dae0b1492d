// The live vtkUnstructuredGrid and the raw views the step loop works on.
#include "grid.hpp"

#include <algorithm>

#include <vtkCellData.h>
#include <vtkCellTypes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdList.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>

#include "error.hpp"

namespace brittle {
namespace {

template <class Array>
Array* add_array(vtkFieldData* data, const char* name, int components, vtkIdType tuples) {
  auto a = vtkSmartPointer<Array>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  a->Fill(0);
  data->AddArray(a);
  return a;
}

double* doubles(vtkFieldData* data, const char* name) {
  auto* a = vtkDoubleArray::SafeDownCast(data->GetAbstractArray(name));
  BRITTLE_CHECK(a, "live grid: array '", name, "' is missing");
  return a->GetPointer(0);
}

}  // namespace

Grid::Grid(vtkUnstructuredGrid& reference_mesh) {
  const vtkIdType np = reference_mesh.GetNumberOfPoints();
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(np);
  for (vtkIdType i = 0; i < np; ++i) points->SetPoint(i, reference_mesh.GetPoint(i));

  auto offsets = vtkSmartPointer<vtkTypeInt64Array>::New();
  auto connectivity = vtkSmartPointer<vtkTypeInt64Array>::New();
  offsets->InsertNextValue(0);
  auto ids = vtkSmartPointer<vtkIdList>::New();
  // Tets; a mesh without any is a 2D body of triangles (mesh.dimension = 2).
  int type = VTK_TETRA;
  corners_ = 4;
  bool tets = false;
  for (vtkIdType c = 0; c < reference_mesh.GetNumberOfCells() && !tets; ++c)
    tets = reference_mesh.GetCellType(c) == VTK_TETRA;
  if (!tets) type = VTK_TRIANGLE, corners_ = 3;
  for (vtkIdType c = 0; c < reference_mesh.GetNumberOfCells(); ++c) {
    if (reference_mesh.GetCellType(c) != type) continue;
    reference_mesh.GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < corners_; ++k) connectivity->InsertNextValue(ids->GetId(k));
    offsets->InsertNextValue(connectivity->GetNumberOfValues());
  }
  BRITTLE_CHECK(connectivity->GetNumberOfValues() > 0,
                "live grid: the mesh has no tetrahedra (nor triangles)");
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->SetData(offsets, connectivity);

  grid_ = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid_->SetPoints(points);
  grid_->SetCells(type, cells);

  const vtkIdType nc = grid_->GetNumberOfCells();
  auto* pd = grid_->GetPointData();
  auto* X = add_array<vtkDoubleArray>(pd, field::reference_position, 3, np);
  for (vtkIdType i = 0; i < np; ++i) X->SetTuple(i, reference_mesh.GetPoint(i));
  add_array<vtkDoubleArray>(pd, field::velocity, 3, np);
  add_array<vtkDoubleArray>(pd, field::displacement, 3, np);
  add_array<vtkDoubleArray>(pd, field::mass, 1, np);
  add_array<vtkUnsignedCharArray>(pd, field::fixed, 1, np);
  add_array<vtkUnsignedCharArray>(pd, field::crack, 1, np);
  // No active vectors: the points are the deformed positions already, and ParaView's Warp By
  // Vector on the active `displacement` would add u a second time (docs/output.md).

  auto* cd = grid_->GetCellData();
  add_array<vtkDoubleArray>(cd, field::damage, 1, nc);
  add_array<vtkDoubleArray>(cd, field::sigma1_over_sigmac, 1, nc);
  add_array<vtkDoubleArray>(cd, field::stress, 6, nc);
  cd->SetActiveScalars(field::sigma1_over_sigmac);

  auto time = vtkSmartPointer<vtkDoubleArray>::New();
  time->SetName(field::time);
  time->SetNumberOfTuples(1);
  time->SetValue(0, 0.0);
  grid_->GetFieldData()->AddArray(time);
  refresh();
}

void Grid::refresh() {
  num_points_ = grid_->GetNumberOfPoints();
  num_cells_ = grid_->GetNumberOfCells();
  x_ = vtkDoubleArray::SafeDownCast(grid_->GetPoints()->GetData())->GetPointer(0);
  auto* pd = grid_->GetPointData();
  X_ = doubles(pd, field::reference_position);
  v_ = doubles(pd, field::velocity);
  u_ = doubles(pd, field::displacement);
  mass_ = doubles(pd, field::mass);
  fixed_ = vtkUnsignedCharArray::SafeDownCast(pd->GetAbstractArray(field::fixed))->GetPointer(0);
  crack_ = vtkUnsignedCharArray::SafeDownCast(pd->GetAbstractArray(field::crack))->GetPointer(0);
  conn_ = grid_->GetCells()->GetConnectivityArray64()->GetPointer(0);
  auto* cd = grid_->GetCellData();
  damage_ = doubles(cd, field::damage);
  sigma1_ = doubles(cd, field::sigma1_over_sigmac);
  stress_ = doubles(cd, field::stress);
}

vtkIdType Grid::split_node(vtkIdType k, const std::vector<vtkIdType>& cells) {
  const vtkIdType b = num_points_;
  const double position[3] = {x_[3 * k], x_[3 * k + 1], x_[3 * k + 2]};
  grid_->GetPoints()->InsertNextPoint(position);
  auto* pd = grid_->GetPointData();
  double tuple[9];
  for (int i = 0; i < pd->GetNumberOfArrays(); ++i) {
    vtkDataArray* a = pd->GetArray(i);
    BRITTLE_ASSERT(a->GetNumberOfComponents() <= 9);
    a->GetTuple(k, tuple);
    a->InsertNextTuple(tuple);
  }
  refresh();
  for (vtkIdType c : cells) {
    vtkIdType* corner = std::find(conn_ + corners_ * c, conn_ + corners_ * c + corners_, k);
    BRITTLE_ASSERT(corner != conn_ + corners_ * c + corners_);
    *corner = b;
  }
  crack_[k] = crack_[b] = 1;
  grid_->GetCells()->Modified();
  return b;
}

void Grid::update_displacement() {
  for (vtkIdType i = 0; i < 3 * num_points_; ++i) u_[i] = x_[i] - X_[i];
}

void Grid::mark_modified() {
  // Every array, not only its container: VTK caches each array's range (written into VTU
  // headers as RangeMin/RangeMax) until the array itself is marked modified.
  grid_->GetPoints()->GetData()->Modified();
  grid_->GetPoints()->Modified();
  for (vtkFieldData* data : {static_cast<vtkFieldData*>(grid_->GetPointData()),
                             static_cast<vtkFieldData*>(grid_->GetCellData()),
                             grid_->GetFieldData()}) {
    for (int i = 0; i < data->GetNumberOfArrays(); ++i)
      if (vtkAbstractArray* a = data->GetAbstractArray(i)) a->Modified();
    data->Modified();
  }
  grid_->Modified();
}

}  // namespace brittle
