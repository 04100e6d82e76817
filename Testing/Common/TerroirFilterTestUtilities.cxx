#include "TerroirFilterTestUtilities.h"

#include "vtkAlgorithm.h"
#include "vtkCallbackCommand.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirDEMReader.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTrivialProducer.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <regex>
#include <sstream>
#include <sys/stat.h>

namespace terroir_test
{

vtkSmartPointer<vtkImageData> MakeTerrain(int nx,
  int ny,
  double dx,
  double dy,
  const std::function<double(int, int)>& z)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(nx, ny, 1);
  image->SetSpacing(dx, dy, 1.0);
  auto elev = vtkSmartPointer<vtkFloatArray>::New();
  elev->SetName("Elevation");
  elev->SetNumberOfTuples(static_cast<vtkIdType>(nx) * ny);
  auto mask = vtkSmartPointer<vtkUnsignedCharArray>::New();
  mask->SetName("vtkValidPointMask");
  mask->SetNumberOfTuples(static_cast<vtkIdType>(nx) * ny);
  bool anyNaN = false;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * nx + i;
      const double v = z(i, j);
      elev->SetValue(k, static_cast<float>(v));
      mask->SetValue(k, std::isnan(v) ? 0 : 1);
      anyNaN = anyNaN || std::isnan(v);
    }
  }
  image->GetPointData()->AddArray(elev);
  if (anyNaN)
  {
    image->GetPointData()->AddArray(mask);
  }
  return image;
}

bool ReadAsciiGrid(const std::string& path, AsciiGrid& grid)
{
  std::ifstream in(path);
  if (!in)
  {
    return false;
  }
  double nodata = -9999.0;
  bool haveNodata = false;
  std::string key;
  std::streampos dataStart;
  for (;;)
  {
    dataStart = in.tellg();
    if (!(in >> key))
    {
      return false;
    }
    std::string lower = key;
    for (auto& c : lower)
    {
      c = static_cast<char>(std::tolower(c));
    }
    if (lower == "ncols")
    {
      in >> grid.nx;
    }
    else if (lower == "nrows")
    {
      in >> grid.ny;
    }
    else if (lower == "cellsize")
    {
      in >> grid.cellSize;
    }
    else if (lower == "nodata_value")
    {
      in >> nodata;
      haveNodata = true;
    }
    else if (lower == "xllcorner" || lower == "yllcorner" || lower == "xllcenter" ||
      lower == "yllcenter" || lower == "dx" || lower == "dy")
    {
      double ignored;
      in >> ignored;
    }
    else
    {
      in.seekg(dataStart);
      break;
    }
  }
  const size_t n = static_cast<size_t>(grid.nx) * grid.ny;
  grid.values.resize(n);
  for (size_t k = 0; k < n; ++k)
  {
    if (!(in >> grid.values[k]))
    {
      return false;
    }
    if (haveNodata && grid.values[k] == nodata)
    {
      grid.values[k] = NAN;
    }
  }
  return grid.nx > 0 && grid.ny > 0;
}

bool WriteAsciiGrid(const std::string& path, vtkImageData* terrain)
{
  int dims[3];
  terrain->GetDimensions(dims);
  vtkDataArray* elev = terrain->GetPointData()->GetArray("Elevation");
  vtkDataArray* mask = terrain->GetPointData()->GetArray("vtkValidPointMask");
  std::ofstream out(path);
  if (!out || !elev)
  {
    return false;
  }
  out << "ncols " << dims[0] << "\nnrows " << dims[1] << "\nxllcorner 0\nyllcorner 0\n"
      << "cellsize " << std::setprecision(17) << terrain->GetSpacing()[0]
      << "\nNODATA_value -9999\n";
  out << std::setprecision(9);
  for (int j = dims[1] - 1; j >= 0; --j)
  {
    for (int i = 0; i < dims[0]; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * dims[0] + i;
      const double v = elev->GetComponent(k, 0);
      const bool ok = !std::isnan(v) && (!mask || mask->GetComponent(k, 0) != 0);
      out << (ok ? v : -9999.0) << (i + 1 < dims[0] ? " " : "\n");
    }
  }
  return static_cast<bool>(out);
}

int RunCommand(const std::string& command)
{
  const int status = std::system(command.c_str());
  return status == 0 ? 0 : (status == -1 ? -1 : (status >> 8) | 1);
}

bool HaveGdaldem()
{
  struct stat st;
  return stat("/usr/bin/gdaldem", &st) == 0;
}

std::string DataFile(const std::string& relative)
{
  return std::string(TERROIR_DATA_DIR) + "/" + relative;
}

std::string TempFile(const std::string& name)
{
  return std::string(TERROIR_TEMP_DIR) + "/" + name;
}

vtkSmartPointer<vtkImageData> ReadDEM(const std::string& path)
{
  auto reader = vtkSmartPointer<vtkTerroirDEMReader>::New();
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* out = reader->GetOutput();
  if (!out || !out->GetPointData()->GetArray("Elevation"))
  {
    return nullptr;
  }
  auto copy = vtkSmartPointer<vtkImageData>::New();
  copy->ShallowCopy(out);
  return copy;
}

std::array<int, 6> RequestedInputExtent(vtkAlgorithm* filter,
  vtkImageData* input,
  const std::array<int, 6>& request)
{
  vtkNew<vtkTrivialProducer> producer;
  producer->SetOutput(input);
  filter->SetInputConnection(producer->GetOutputPort());
  filter->UpdateInformation();
  std::array<int, 6> asked = request;
  filter->UpdateExtent(asked.data());
  std::array<int, 6> got{};
  filter->GetInputInformation(0, 0)->Get(
    vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), got.data());
  return got;
}

std::vector<double> UpdateWithProgress(vtkAlgorithm* filter)
{
  std::vector<double> progress;
  vtkNew<vtkCallbackCommand> cb;
  cb->SetClientData(&progress);
  cb->SetCallback([](vtkObject*, unsigned long, void* client, void* data)
    { static_cast<std::vector<double>*>(client)->push_back(*static_cast<double*>(data)); });
  const unsigned long tag = filter->AddObserver(vtkCommand::ProgressEvent, cb);
  filter->Update();
  filter->RemoveObserver(tag);
  return progress;
}

void ErrorObserver::Execute(vtkObject*, unsigned long event, void* data)
{
  const char* text = static_cast<const char*>(data);
  if (event == vtkCommand::ErrorEvent)
  {
    this->Errors += text ? text : "";
    this->Errors += "\n";
    ++this->ErrorCount;
  }
  else if (event == vtkCommand::WarningEvent)
  {
    this->Warnings += text ? text : "";
    this->Warnings += "\n";
  }
}

bool GPUAvailable(bool& mustFail, std::string& reason)
{
  auto& ctx = terroir::gpu::Context::Global();
  const bool ok = ctx.IsAvailable();
  reason = ok ? std::string() : ctx.UnavailableReason();
  const char* req = std::getenv("TERROIR_REQUIRE_GPU");
  mustFail = !ok && req && std::string(req) == "1";
  return ok;
}

std::vector<AlgorithmClass> ProjectAlgorithmClasses()
{
  namespace fs = std::filesystem;
  const std::regex declaration(
    R"(class\s+VTKTERROIR\w+_EXPORT\s+(vtkTerroir\w+)\s*:\s*public\s+(\w+))");
  const std::regex algorithmBase(R"(.*(Algorithm|Writer|Reader|Source)$)");
  std::vector<AlgorithmClass> classes;
  const fs::path root(TERROIR_SOURCE_DIR);
  for (const char* folder : { "Common", "Compute", "Filters", "IO", "Rendering" })
  {
    std::error_code ec;
    for (const auto& entry : fs::recursive_directory_iterator(root / folder, ec))
    {
      const fs::path& p = entry.path();
      if (p.extension() != ".h" || p.filename().string().rfind("vtkTerroir", 0) != 0)
      {
        continue;
      }
      std::ifstream in(p);
      std::stringstream text;
      text << in.rdbuf();
      const std::string header = text.str();
      std::smatch m;
      // Abstract bases have no New().
      if (!std::regex_search(header, m, declaration) ||
        !std::regex_match(m[2].str(), algorithmBase) ||
        header.find("static " + m[1].str() + "* New()") == std::string::npos)
      {
        continue;
      }
      AlgorithmClass c;
      c.Name = m[1].str();
      c.Header = p.string();
      c.HasGPUPath = std::regex_search(
        header, std::regex(R"(bool\s+HasGPUPath\(\)\s+override\s*\{\s*return\s+true;)"));
      classes.push_back(c);
    }
  }
  std::sort(classes.begin(),
    classes.end(),
    [](const AlgorithmClass& a, const AlgorithmClass& b) { return a.Name < b.Name; });
  return classes;
}

} // namespace terroir_test
