#include "vtkTerroirInfiltration.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkImageStencilData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirTerrainInput.h"

#include "SlopeHorn1981.h"
#include "SoilWater.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTerroirInfiltration);

namespace
{
enum class OperationType
{
  Fill,
  SlopeRule,
  PaintMask,
  PaintMaskArray,
  PaintStencil,
  SoilTypes,
  SoilTypeArray
};

const char* OperationName(OperationType t)
{
  switch (t)
  {
    case OperationType::Fill:
      return "Fill";
    case OperationType::SlopeRule:
      return "SlopeRule";
    case OperationType::PaintMask:
      return "PaintMask";
    case OperationType::PaintMaskArray:
      return "PaintMaskArray";
    case OperationType::PaintStencil:
      return "PaintStencil";
    case OperationType::SoilTypes:
      return "SoilTypes";
    case OperationType::SoilTypeArray:
      return "SoilTypeArray";
  }
  return "?";
}

struct Operation
{
  OperationType Type;
  double Value = 0.0; ///< rate (mm/h) or slope threshold (degrees)
  std::string ArrayName;
  vtkSmartPointer<vtkImageData> Image;
  vtkSmartPointer<vtkImageStencilData> Stencil;
};

/// The single-component array an operation reads: `name` on `image`, or the image's active
/// scalars, else its first point array. Null when there is none.
vtkDataArray* OperandArray(vtkImageData* image, const std::string& name)
{
  vtkPointData* pd = image ? image->GetPointData() : nullptr;
  if (!pd)
  {
    return nullptr;
  }
  if (!name.empty())
  {
    return pd->GetArray(name.c_str());
  }
  if (pd->GetScalars())
  {
    return pd->GetScalars();
  }
  return pd->GetNumberOfArrays() > 0 ? pd->GetArray(0) : nullptr;
}

bool RateOK(double r)
{
  return r >= 0.0 && r <= vtkTerroirInfiltration::GetMaximumRate();
}

/// The default recipe, used when no operation was added: Fill 15, SlopeRule 30.
std::vector<Operation> DefaultOperations()
{
  Operation fill{ OperationType::Fill };
  fill.Value = 15.0;
  Operation rule{ OperationType::SlopeRule };
  rule.Value = 30.0;
  return { fill, rule };
}

/// SlopeRule at `degrees`: the input's Slope array (in its units, degrees or %), else the slope
/// of the terrain (computed once into slopeStorage). An error message, or empty.
std::string ApplySlopeRule(vtkImageData* input,
  const terroir::GridView<float>& v,
  double degrees,
  std::vector<float>& slopeStorage,
  float* rate)
{
  const std::size_t n = v.Size();
  vtkDataArray* slopeArray = input->GetPointData()->GetArray("Slope");
  double threshold = degrees;
  const float* slope = nullptr;
  std::vector<float> converted;
  if (slopeArray && slopeArray->GetNumberOfComponents() == 1 &&
    slopeArray->GetNumberOfTuples() == static_cast<vtkIdType>(n))
  {
    vtkInformation* info = slopeArray->GetInformation();
    const char* units =
      info->Has(vtkDataArray::UNITS_LABEL()) ? info->Get(vtkDataArray::UNITS_LABEL()) : "";
    if (std::string(units) == "%")
    {
      threshold = degrees >= 90.0 ? std::numeric_limits<double>::infinity()
                                  : 100.0 * std::tan(degrees * M_PI / 180.0);
    }
    if (auto* f = vtkFloatArray::FastDownCast(slopeArray))
    {
      slope = f->GetPointer(0);
    }
    else
    {
      converted.resize(n);
      for (std::size_t c = 0; c < n; ++c)
      {
        converted[c] = static_cast<float>(slopeArray->GetComponent(c, 0));
      }
      slope = converted.data();
    }
  }
  else
  {
    if (v.nx < 2 || v.ny < 2)
    {
      return "the slope rule needs a terrain of at least 2 x 2 cells or a Slope array";
    }
    if (slopeStorage.empty())
    {
      slopeStorage.resize(n);
      terroir::terrain::SlopeParams params;
      terroir::terrain::SlopeHorn1981(
        v, params, slopeStorage.data(), static_cast<float*>(nullptr), static_cast<float*>(nullptr));
    }
    slope = slopeStorage.data();
  }
  terroir::terrain::ApplySlopeRule(slope, threshold, rate, 0, n);
  return std::string();
}

/// PaintMask, PaintMaskArray, SoilTypes and SoilTypeArray: the rate where the operand array (of
/// the operation's image or of the input) is non-zero, or the rate of its soil type 1..5. An
/// error message, or empty.
std::string PaintFromArray(vtkImageData* input,
  const Operation& op,
  std::size_t n,
  const double soilTypeRates[5],
  float* rate)
{
  const bool fromInput =
    op.Type == OperationType::PaintMaskArray || op.Type == OperationType::SoilTypeArray;
  vtkImageData* source = fromInput ? input : op.Image.Get();
  vtkDataArray* a = OperandArray(source, op.ArrayName);
  if (!a)
  {
    return fromInput ? "the terrain has no point array '" + op.ArrayName + "'"
                     : std::string("the image has no point array");
  }
  if (!fromInput)
  {
    int dims[3];
    input->GetDimensions(dims);
    int d[3];
    source->GetDimensions(d);
    if (d[0] != dims[0] || d[1] != dims[1] || d[2] != 1)
    {
      std::ostringstream message;
      message << "the image has " << d[0] << " x " << d[1] << " x " << d[2]
              << " cells, the terrain " << dims[0] << " x " << dims[1]
              << "; resample it onto the terrain's grid first";
      return message.str();
    }
  }
  if (a->GetNumberOfComponents() != 1 || a->GetNumberOfTuples() != static_cast<vtkIdType>(n))
  {
    std::ostringstream message;
    message << "array '" << (a->GetName() ? a->GetName() : "") << "' must have 1 component and "
            << n << " tuples, not " << a->GetNumberOfComponents() << " and "
            << a->GetNumberOfTuples();
    return message.str();
  }
  const bool soil = op.Type == OperationType::SoilTypes || op.Type == OperationType::SoilTypeArray;
  const float value = static_cast<float>(op.Value);
  vtkSMPTools::For(0,
    static_cast<vtkIdType>(n),
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType c = begin; c < end; ++c)
      {
        const double m = a->GetComponent(c, 0);
        if (soil)
        {
          const double code = std::round(m);
          if (m == code && code >= 1.0 && code <= 5.0)
          {
            rate[c] = static_cast<float>(soilTypeRates[static_cast<int>(code) - 1]);
          }
        }
        else if (m != 0.0 && !std::isnan(m))
        {
          rate[c] = value;
        }
      }
    });
  return std::string();
}

/// PaintStencil: `value` on the cells inside the stencil (in the input's extent).
void PaintStencil(vtkImageData* input,
  const terroir::GridView<float>& v,
  vtkImageStencilData* stencil,
  float value,
  float* rate)
{
  int extent[6];
  input->GetExtent(extent);
  for (int j = 0; j < v.ny; ++j)
  {
    int iter = 0;
    int r1 = 0;
    int r2 = 0;
    const int y = extent[2] + j;
    while (stencil->GetNextExtent(r1, r2, extent[0], extent[1], y, extent[4], iter))
    {
      for (int i = r1; i <= r2; ++i)
      {
        rate[v.Index(i - extent[0], j)] = value;
      }
    }
  }
}

/// Operation `op` on `rate` (the terrain's cells); an error message, or empty.
std::string ApplyOperation(vtkImageData* input,
  const terroir::GridView<float>& v,
  const Operation& op,
  const double soilTypeRates[5],
  std::vector<float>& slopeStorage,
  float* rate)
{
  const std::size_t n = v.Size();
  const float value = static_cast<float>(op.Value);
  switch (op.Type)
  {
    case OperationType::Fill:
      std::fill(rate, rate + n, value);
      break;
    case OperationType::SlopeRule:
      return ApplySlopeRule(input, v, op.Value, slopeStorage, rate);
    case OperationType::PaintMask:
    case OperationType::PaintMaskArray:
    case OperationType::SoilTypes:
    case OperationType::SoilTypeArray:
      return PaintFromArray(input, op, n, soilTypeRates, rate);
    case OperationType::PaintStencil:
      PaintStencil(input, v, op.Stencil, value, rate);
      break;
  }
  return std::string();
}
} // namespace

struct vtkTerroirInfiltration::Internals
{
  std::vector<Operation> Operations;
};

//------------------------------------------------------------------------------
vtkTerroirInfiltration::vtkTerroirInfiltration()
  : Impl(new Internals)
{
}

//------------------------------------------------------------------------------
vtkTerroirInfiltration::~vtkTerroirInfiltration()
{
  delete this->Impl;
}

//------------------------------------------------------------------------------
void vtkTerroirInfiltration::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Operations: " << this->Impl->Operations.size()
     << (this->Impl->Operations.empty() ? " (default recipe: Fill 15, SlopeRule 30)" : "") << "\n";
  for (const Operation& op : this->Impl->Operations)
  {
    os << indent.GetNextIndent() << OperationName(op.Type);
    if (op.Type != OperationType::SoilTypes && op.Type != OperationType::SoilTypeArray)
    {
      os << " " << op.Value;
    }
    if (!op.ArrayName.empty())
    {
      os << " array '" << op.ArrayName << "'";
    }
    if (op.Image)
    {
      os << " image " << op.Image.Get();
    }
    if (op.Stencil)
    {
      os << " stencil " << op.Stencil.Get();
    }
    os << "\n";
  }
  os << indent << "SoilTypeRates:";
  for (double r : this->SoilTypeRates)
  {
    os << " " << r;
  }
  os << "\n";
}

//------------------------------------------------------------------------------
void vtkTerroirInfiltration::AddFill(double rate)
{
  Operation op{ OperationType::Fill };
  op.Value = rate;
  this->Impl->Operations.push_back(op);
  this->Modified();
}

void vtkTerroirInfiltration::AddSlopeRule(double thresholdDegrees)
{
  Operation op{ OperationType::SlopeRule };
  op.Value = thresholdDegrees;
  this->Impl->Operations.push_back(op);
  this->Modified();
}

void vtkTerroirInfiltration::AddPaintMask(vtkImageData* mask, double rate)
{
  Operation op{ OperationType::PaintMask };
  op.Value = rate;
  op.Image = mask;
  this->Impl->Operations.push_back(op);
  this->Modified();
}

void vtkTerroirInfiltration::AddPaintMaskArray(const char* arrayName, double rate)
{
  Operation op{ OperationType::PaintMaskArray };
  op.Value = rate;
  op.ArrayName = arrayName ? arrayName : "";
  this->Impl->Operations.push_back(op);
  this->Modified();
}

void vtkTerroirInfiltration::AddPaintStencil(vtkImageStencilData* stencil, double rate)
{
  Operation op{ OperationType::PaintStencil };
  op.Value = rate;
  op.Stencil = stencil;
  this->Impl->Operations.push_back(op);
  this->Modified();
}

void vtkTerroirInfiltration::AddSoilTypes(vtkImageData* soilTypes)
{
  Operation op{ OperationType::SoilTypes };
  op.Image = soilTypes;
  this->Impl->Operations.push_back(op);
  this->Modified();
}

void vtkTerroirInfiltration::AddSoilTypeArray(const char* arrayName)
{
  Operation op{ OperationType::SoilTypeArray };
  op.ArrayName = arrayName ? arrayName : "";
  this->Impl->Operations.push_back(op);
  this->Modified();
}

void vtkTerroirInfiltration::RemoveAllOperations()
{
  if (!this->Impl->Operations.empty())
  {
    this->Impl->Operations.clear();
    this->Modified();
  }
}

void vtkTerroirInfiltration::SetFillAndSlopeRule(double rate, double thresholdDegrees)
{
  this->Impl->Operations.clear();
  this->AddFill(rate);
  this->AddSlopeRule(thresholdDegrees);
}

int vtkTerroirInfiltration::GetNumberOfOperations()
{
  return static_cast<int>(this->Impl->Operations.size());
}

//------------------------------------------------------------------------------
void vtkTerroirInfiltration::SetSoilTypeRate(int code, double rate)
{
  if (code < 1 || code > 5)
  {
    vtkErrorMacro(<< "soil type " << code << " is not one of 1 (sand) .. 5 (clay)");
    return;
  }
  if (this->SoilTypeRates[code - 1] != rate)
  {
    this->SoilTypeRates[code - 1] = rate;
    this->Modified();
  }
}

double vtkTerroirInfiltration::GetSoilTypeRate(int code)
{
  return code >= 1 && code <= 5 ? this->SoilTypeRates[code - 1]
                                : std::numeric_limits<double>::quiet_NaN();
}

//------------------------------------------------------------------------------
vtkMTimeType vtkTerroirInfiltration::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  for (const Operation& op : this->Impl->Operations)
  {
    if (op.Image)
    {
      t = std::max(t, op.Image->GetMTime());
    }
    if (op.Stencil)
    {
      t = std::max(t, op.Stencil->GetMTime());
    }
  }
  return t;
}

//------------------------------------------------------------------------------
double vtkTerroirInfiltration::EstimateMemory(double nx, double ny)
{
  // InfiltrationRate (4 B per cell); a computed slope (4 B); a float copy of a non-float mask
  // is not made (masks are read in place).
  return nx * ny * 8.0;
}

//------------------------------------------------------------------------------
std::string vtkTerroirInfiltration::CheckParameters()
{
  for (std::size_t k = 0; k < this->Impl->Operations.size(); ++k)
  {
    const Operation& op = this->Impl->Operations[k];
    const std::string which =
      "operation " + std::to_string(k + 1) + " (" + OperationName(op.Type) + "): ";
    switch (op.Type)
    {
      case OperationType::SlopeRule:
        if (!(op.Value >= 0.0 && op.Value <= 90.0))
        {
          return which + "slope threshold " + std::to_string(op.Value) +
            " degrees is outside [0, 90]";
        }
        break;
      case OperationType::SoilTypes:
      case OperationType::SoilTypeArray:
        break;
      default:
        if (!RateOK(op.Value))
        {
          return which + "infiltration rate " + std::to_string(op.Value) +
            " mm/h is outside [0, 1000]";
        }
    }
    if ((op.Type == OperationType::PaintMask || op.Type == OperationType::SoilTypes) && !op.Image)
    {
      return which + "no image given";
    }
    if (op.Type == OperationType::PaintStencil && !op.Stencil)
    {
      return which + "no stencil given";
    }
    if ((op.Type == OperationType::PaintMaskArray || op.Type == OperationType::SoilTypeArray) &&
      op.ArrayName.empty())
    {
      return which + "no array name given";
    }
  }
  for (int c = 0; c < 5; ++c)
  {
    if (!RateOK(this->SoilTypeRates[c]))
    {
      return "rate of soil type " + std::to_string(c + 1) + " " +
        std::to_string(this->SoilTypeRates[c]) + " mm/h is outside [0, 1000]";
    }
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkTerroirInfiltration::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  vtkSmartPointer<vtkFloatArray> rateArray = vtkSmartPointer<vtkFloatArray>::Take(
    terroir::NewOutputArray(InfiltrationRateName(), 1, static_cast<long long>(n), "mm/h"));
  float* rate = rateArray->GetPointer(0);
  std::fill(rate, rate + n, 0.0f);
  this->SelectBackend(false);

  const std::vector<Operation> ops =
    this->Impl->Operations.empty() ? DefaultOperations() : this->Impl->Operations;
  const std::string prefix = this->SourcePrefix(input);
  std::vector<float> slopeStorage; // computed once, when the input has no Slope array
  for (std::size_t k = 0; k < ops.size(); ++k)
  {
    const Operation& op = ops[k];
    const std::string error = ApplyOperation(input, v, op, this->SoilTypeRates, slopeStorage, rate);
    if (!error.empty())
    {
      vtkErrorMacro(<< prefix << "operation " << (k + 1) << " (" << OperationName(op.Type)
                    << "): " << error);
      return 0;
    }
    this->UpdateProgress(0.9 * static_cast<double>(k + 1) / static_cast<double>(ops.size()));
  }
  if (terrain.hasNoData)
  {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t c = 0; c < n; ++c)
    {
      if (v.valid && !v.valid[c])
      {
        rate[c] = nan;
      }
    }
  }
  output->GetPointData()->AddArray(rateArray);
  return 1;
}
