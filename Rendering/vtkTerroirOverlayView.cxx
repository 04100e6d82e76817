#include "vtkTerroirOverlayView.h"

#include "ClusterPalette.h"
#include "TerroirSafeOutput.h"

#include "vtkActor.h"
#include "vtkActor2D.h"
#include "vtkAutoInit.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkConeSource.h"
#include "vtkCoordinate.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkGlyph3DMapper.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkLookupTable.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataMapper2D.h"
#include "vtkProperty.h"
#include "vtkProperty2D.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkRendererCollection.h"
#include "vtkScalarBarActor.h"
#include "vtkShaderProperty.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirColorPresets.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirOverlayLegend.h"
#include "vtkTerroirReliefSurface.h"
#include "vtkTerroirTerrainTexture.h"
#include "vtkTerroirXDisplay.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkTexture.h"
#include "vtkUniforms.h"
#include "vtkUnsignedCharArray.h"
#include "vtkWindowToImageFilter.h"

#include <vtksys/SystemTools.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include <unistd.h>

// Register the OpenGL render window and FreeType text factories whenever this library is
// loaded, so that C++ programs and Python scripts need no vtk_module_autoinit of their own.
VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingFreeType);

vtkStandardNewMacro(vtkTerroirOverlayView);

struct vtkTerroirOverlayView::Internals
{
  vtkSmartPointer<vtkImageData> Input;
  vtkSmartPointer<vtkPolyData> Plants;
  // Kept from one Render() to the next (one view draws a run's overlays in turn): the window
  // with its X connection and compiled shaders, and the surface while its geometry is current.
  vtkSmartPointer<vtkRenderWindow> Window;
  void* Display = nullptr; // X11 Display* owned by us, used by Window
  vtkSmartPointer<vtkTerroirReliefSurface> Relief;
  // What the surface was built from: the arrays (held, so that their addresses stay theirs),
  // their modification times, the grid and the exaggeration.
  struct GeometryKey
  {
    vtkSmartPointer<vtkDataArray> Elevation, Mask;
    vtkMTimeType ElevationTime = 0, MaskTime = 0;
    int Dims[3] = { 0, 0, 0 };
    double Origin[3] = { 0, 0, 0 }, Spacing[3] = { 0, 0, 0 };
    double VerticalExaggeration = 0.0;
    int Stride = 1;
    bool operator==(const GeometryKey& o) const
    {
      return this->Elevation == o.Elevation && this->Mask == o.Mask &&
        this->ElevationTime == o.ElevationTime && this->MaskTime == o.MaskTime &&
        std::equal(this->Dims, this->Dims + 3, o.Dims) &&
        std::equal(this->Origin, this->Origin + 3, o.Origin) &&
        std::equal(this->Spacing, this->Spacing + 3, o.Spacing) &&
        this->VerticalExaggeration == o.VerticalExaggeration && this->Stride == o.Stride;
    }
  } Built;

  static GeometryKey KeyOf(vtkImageData* image, double verticalExaggeration, int stride)
  {
    GeometryKey key;
    vtkPointData* pd = image->GetPointData();
    key.Elevation = pd->GetArray(vtkTerroirGeoreference::ElevationName());
    key.Mask = pd->GetArray(vtkTerroirGeoreference::ValidMaskName());
    key.ElevationTime = key.Elevation ? key.Elevation->GetMTime() : 0;
    key.MaskTime = key.Mask ? key.Mask->GetMTime() : 0;
    image->GetDimensions(key.Dims);
    image->GetOrigin(key.Origin);
    image->GetSpacing(key.Spacing);
    key.VerticalExaggeration = verticalExaggeration;
    key.Stride = stride;
    return key;
  }

  // Texturing: whether the kept surface carries a texture (then it is rebuilt when texturing
  // is turned off, so that the untextured surface is exactly the one without the option), and
  // the last texture with what it was built from.
  bool Textured = false;
  vtkNew<vtkTerroirTerrainTexture> Texture;

  // The window goes first: it must not outlive the connection it draws through.
  void ReleaseWindow()
  {
    if (this->Window)
    {
      this->Window->Finalize();
      this->Window = nullptr;
    }
    terroir::rendering::CloseXDisplay(this->Display);
    this->Display = nullptr;
  }
  ~Internals()
  {
    this->Relief = nullptr;
    this->ReleaseWindow();
  }
};

//------------------------------------------------------------------------------
vtkTerroirOverlayView::vtkTerroirOverlayView()
  : Internal(new Internals)
{
  this->SetArrayName(vtkTerroirGeoreference::ElevationName());
}

vtkTerroirOverlayView::~vtkTerroirOverlayView()
{
  this->SetArrayName(nullptr);
  this->SetPreset(nullptr);
  this->SetTitle(nullptr);
}

void vtkTerroirOverlayView::SetInputData(vtkImageData* terrain)
{
  if (this->Internal->Input != terrain)
  {
    this->Internal->Input = terrain;
    this->Modified();
  }
}

vtkImageData* vtkTerroirOverlayView::GetInputData()
{
  return this->Internal->Input;
}

const char* vtkTerroirOverlayView::GetEffectivePreset()
{
  if (this->Preset && *this->Preset)
  {
    return this->Preset;
  }
  const char* p = vtkTerroirColorPresets::GetPresetForArray(this->ArrayName);
  return p ? p : "Elevation";
}

bool vtkTerroirOverlayView::Fail(const std::string& message)
{
  this->LastError = message;
  vtkErrorMacro(<< message);
  return false;
}

//------------------------------------------------------------------------------
bool vtkTerroirOverlayView::CheckInput(vtkImageData* image,
  vtkDataArray*& values,
  const char*& preset)
{
  if (!image)
  {
    return this->Fail("vtkTerroirOverlayView: no input terrain (call SetInputData)");
  }
  int dims[3];
  image->GetDimensions(dims);
  if (dims[2] != 1 || dims[0] < 2 || dims[1] < 2)
  {
    return this->Fail("vtkTerroirOverlayView: the terrain must be a 2-D image of at least 2x2 "
                      "points, got " +
      std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]));
  }
  vtkPointData* pd = image->GetPointData();
  vtkDataArray* elevation = pd->GetArray(vtkTerroirGeoreference::ElevationName());
  if (!elevation || elevation->GetNumberOfComponents() != 1)
  {
    return this->Fail(
      "vtkTerroirOverlayView: the terrain has no one-component 'Elevation' point array");
  }
  const char* arrayName = this->ArrayName ? this->ArrayName : "";
  values = pd->GetArray(arrayName);
  if (!values)
  {
    return this->Fail(
      std::string("vtkTerroirOverlayView: the terrain has no point array '") + arrayName + "'");
  }
  if (this->ArrayComponent >= values->GetNumberOfComponents())
  {
    return this->Fail(std::string("vtkTerroirOverlayView: array '") + arrayName + "' has " +
      std::to_string(values->GetNumberOfComponents()) + " component(s); component " +
      std::to_string(this->ArrayComponent) + " requested");
  }
  preset = this->GetEffectivePreset();
  if (!vtkTerroirColorPresets::HasPreset(preset))
  {
    return this->Fail(std::string("vtkTerroirOverlayView: unknown colour preset '") + preset + "'");
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkTerroirOverlayView::ColourSurface(vtkImageData* image,
  vtkDataArray* values,
  const char* preset,
  vtkTerroirReliefSurface* relief,
  vtkLookupTable* lut,
  std::string& categoricalTitle)
{
  const int comp = this->ArrayComponent;
  const vtkIdType n = image->GetNumberOfPoints();
  // A preset's mask array (WaterBodies: WaterBody) leaves its zero cells uncoloured.
  const char* maskName = vtkTerroirColorPresets::GetMaskArrayName(preset);
  vtkDataArray* bodyMask = maskName ? image->GetPointData()->GetArray(maskName) : nullptr;
  if (bodyMask && (bodyMask->GetNumberOfComponents() != 1 || bodyMask->GetNumberOfTuples() != n))
  {
    bodyMask = nullptr;
  }
  double range[2];
  if (this->UseCustomRange)
  {
    range[0] = this->Range[0];
    range[1] = this->Range[1];
  }
  else if (!vtkTerroirColorPresets::GetDefaultRange(preset, range) &&
    !relief->ComputeDataRange(values, comp, bodyMask, range))
  {
    range[0] = 0.0;
    range[1] = 1.0;
  }
  if (!vtkTerroirColorPresets::ConfigureLookupTable(lut, preset, range[0], range[1]))
  {
    return this->Fail("vtkTerroirOverlayView: invalid colour range [" + std::to_string(range[0]) +
      ", " + std::to_string(range[1]) + "]");
  }
  lut->SetNanColor(this->NanColor);
  categoricalTitle = vtkTerroirOverlayLegend::ApplyClusterShares(lut, preset, image);
  this->LastRange[0] = range[0];
  this->LastRange[1] = range[1];
  relief->SetColors(values, comp, lut, bodyMask);
  return true;
}

//------------------------------------------------------------------------------
void vtkTerroirOverlayView::SetPlantsData(vtkPolyData* plants)
{
  if (this->Internal->Plants != plants)
  {
    this->Internal->Plants = plants;
    this->Modified();
  }
}

//------------------------------------------------------------------------------
vtkPolyData* vtkTerroirOverlayView::GetPlantsData()
{
  return this->Internal->Plants;
}

//------------------------------------------------------------------------------
vtkSmartPointer<vtkActor> vtkTerroirOverlayView::MakePlantsActor()
{
  // The plants' points on the exaggerated surface, each glyph's base on the ground.
  vtkPolyData* plants = this->Internal->Plants;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(plants->GetNumberOfPoints());
  for (vtkIdType p = 0; p < plants->GetNumberOfPoints(); ++p)
  {
    double x[3];
    plants->GetPoint(p, x);
    points->SetPoint(p, x[0], x[1], x[2] * this->VerticalExaggeration + 0.5 * this->PlantSize);
  }
  vtkNew<vtkPolyData> placed;
  placed->SetPoints(points);
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetName("PlantColours");
  colours->SetNumberOfComponents(3);
  colours->SetNumberOfTuples(plants->GetNumberOfPoints());
  vtkDataArray* species = plants->GetPointData()->GetArray("Species");
  for (vtkIdType p = 0; p < plants->GetNumberOfPoints(); ++p)
  {
    const double s = species ? species->GetComponent(p, 0) : 0.0;
    // Green first (the palette's third colour), so that plants stand out from the zones' blue
    // and orange.
    const int k =
      (std::isfinite(s) && s >= 0.0 ? static_cast<int>(s) + 2 : 2) % terroir::kClusterPaletteSize;
    for (int c = 0; c < 3; ++c)
    {
      colours->SetTypedComponent(p, c, terroir::kClusterPalette[k][c]);
    }
  }
  placed->GetPointData()->SetScalars(colours);
  vtkNew<vtkConeSource> cone;
  cone->SetHeight(this->PlantSize);
  cone->SetRadius(0.25 * this->PlantSize);
  cone->SetDirection(0.0, 0.0, 1.0);
  cone->SetResolution(12);
  vtkNew<vtkGlyph3DMapper> mapper;
  mapper->SetInputData(placed);
  mapper->SetSourceConnection(cone->GetOutputPort());
  mapper->ScalingOff();
  mapper->OrientOff();
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectColorArray("PlantColours");
  mapper->SetColorModeToDirectScalars();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  // The terrain's lighting (Ambient, Diffuse of the view; no highlight on the foliage).
  actor->GetProperty()->SetAmbient(this->Ambient);
  actor->GetProperty()->SetDiffuse(this->Diffuse);
  actor->GetProperty()->SetSpecular(0.0);
  return actor;
}

//------------------------------------------------------------------------------
void vtkTerroirOverlayView::AddTerrainRenderer(vtkRenderWindow* window,
  vtkTerroirReliefSurface* relief,
  double legendWidth,
  double titleHeight)
{
  vtkNew<vtkRenderer> renderer;
  renderer->SetViewport(0.0, 0.0, 1.0 - legendWidth, 1.0 - titleHeight);
  renderer->SetBackground(this->Background);
  renderer->AutomaticLightCreationOff();
  renderer->AddActor(relief->GetSurfaceActor());
  renderer->AddActor(relief->GetHoleActor());
  if (this->Internal->Plants && this->Internal->Plants->GetNumberOfPoints() > 0 &&
    this->PlantSize > 0.0)
  {
    renderer->AddActor(this->MakePlantsActor());
  }

  double bounds[6];
  relief->GetBounds(bounds);
  const double aspect = ((1.0 - legendWidth) * this->Width) / ((1.0 - titleHeight) * this->Height);
  vtkNew<vtkLight> light;
  vtkTerroirReliefSurface::ConfigureLight(light, this->LightAzimuth, this->LightElevation, bounds);
  renderer->AddLight(light);

  vtkCamera* camera = renderer->GetActiveCamera();
  if (this->Mode == Map)
  {
    vtkTerroirReliefSurface::FitMapCamera(camera, bounds, aspect);
  }
  else
  {
    vtkTerroirReliefSurface::FitReliefCamera(camera,
      bounds,
      aspect,
      GetReliefCameraAzimuth(),
      GetReliefCameraElevation(),
      GetReliefViewAngle());
  }
  renderer->ResetCameraClippingRange(bounds);
  window->AddRenderer(renderer);
}

//------------------------------------------------------------------------------
void vtkTerroirOverlayView::AddTitleRenderer(vtkRenderWindow* window,
  double titleHeight,
  double textGrey)
{
  vtkNew<vtkRenderer> titleRenderer;
  titleRenderer->SetViewport(0.0, 1.0 - titleHeight, 1.0, 1.0);
  titleRenderer->SetBackground(this->Background);
  vtkNew<vtkTextActor> title;
  title->SetInput(this->Title);
  vtkTextProperty* tp = title->GetTextProperty();
  tp->SetFontSize(std::max(10, static_cast<int>(0.6 * titleHeight * this->Height)));
  tp->SetColor(textGrey, textGrey, textGrey);
  tp->SetJustificationToCentered();
  tp->SetVerticalJustificationToCentered();
  tp->BoldOn();
  title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  title->SetPosition(0.5, 0.5);
  titleRenderer->AddActor2D(title);
  window->AddRenderer(titleRenderer);
}

//------------------------------------------------------------------------------
bool vtkTerroirOverlayView::Render()
{
  this->LastError.clear();
  vtkImageData* image = this->Internal->Input;
  vtkDataArray* values = nullptr;
  const char* preset = nullptr;
  if (!this->CheckInput(image, values, preset))
  {
    return false;
  }
  std::string why;
  vtkTerroirReliefSurface* relief = this->PrepareSurface(image, why);
  if (!relief)
  {
    return this->Fail("vtkTerroirOverlayView: " + why);
  }
  vtkNew<vtkLookupTable> lut;
  std::string categoricalTitle;
  if (!this->ColourSurface(image, values, preset, relief, lut, categoricalTitle))
  {
    return false;
  }
  if (this->Texturing && !this->ApplyTexture(image, relief))
  {
    return false;
  }
  vtkRenderWindow* window = this->PrepareWindow(why);
  if (!window)
  {
    return this->Fail("vtkTerroirOverlayView: " + why);
  }

  // Layout: the legend takes the right quarter, the title a strip at the top (8% of the
  // height, at least 24 pixels); the terrain gets the rest.
  const double legendWidth = this->LegendShown() ? 0.25 : 0.0;
  const bool hasTitle = this->Title && *this->Title;
  const double titleHeight = hasTitle ? std::max(0.08, 24.0 / this->Height) : 0.0;
  const double luminance =
    0.2126 * this->Background[0] + 0.7152 * this->Background[1] + 0.0722 * this->Background[2];
  const double textGrey = luminance > 0.5 ? 0.0 : 1.0;
  this->AddTerrainRenderer(window, relief, legendWidth, titleHeight);
  if (hasTitle)
  {
    this->AddTitleRenderer(window, titleHeight, textGrey);
  }
  if (this->LegendShown())
  {
    vtkNew<vtkRenderer> legendRenderer;
    legendRenderer->SetViewport(1.0 - legendWidth, 0.0, 1.0, 1.0 - titleHeight);
    legendRenderer->SetBackground(this->Background);
    const int fontSize = std::max(8, this->Height / 36);
    vtkTerroirOverlayLegend::AddLegend(
      legendRenderer, lut, preset, categoricalTitle, fontSize, textGrey, this->Background);
    window->AddRenderer(legendRenderer);
  }
  window->Render();
  return true;
}

//------------------------------------------------------------------------------
bool vtkTerroirOverlayView::ApplyTexture(vtkImageData* image, vtkTerroirReliefSurface* relief)
{
  Internals& in = *this->Internal;
  vtkTerroirTerrainTexture* texture = in.Texture;
  texture->SetSeed(this->TextureSeed);
  texture->SetTexelsPerCell(this->TexelsPerCell);
  texture->SetMaxTextureSize(this->MaxTextureSize);
  texture->SetSeaLevel(this->TextureSeaLevel);
  texture->SetSnowLine(this->TextureSnowLine);
  std::string error;
  if (!texture->ApplyTo(relief, image, error))
  {
    return this->Fail("vtkTerroirOverlayView: " + error);
  }
  texture->GetTextureSize(this->LastTextureSize);
  this->LastCellsPerTile = texture->GetCellsPerTile();
  in.Textured = true;
  return true;
}

//------------------------------------------------------------------------------
vtkTerroirReliefSurface* vtkTerroirOverlayView::PrepareSurface(vtkImageData* image,
  std::string& why)
{
  // Surface (points, validity, normals, no-data holes): built again only when the terrain's
  // elevation, mask, grid or exaggeration changed since the last Render().
  // A grid with more points than the terrain's part of the frame has pixels is drawn at every
  // Stride-th point: the rasteriser would sample no more of it (on the bundled 786 x 720 DEM
  // in an 800 x 600 frame, every point is drawn).
  Internals& in = *this->Internal;
  int dims[3];
  image->GetDimensions(dims);
  const double frameWidth = this->Width * (this->LegendShown() ? 0.75 : 1.0);
  const double titleShare = this->Title && *this->Title ? std::max(0.08, 24.0 / this->Height) : 0.0;
  const double frameHeight = this->Height * (1.0 - titleShare);
  const int stride = std::max(
    1, static_cast<int>(std::floor(std::min(dims[0] / frameWidth, dims[1] / frameHeight))));
  const Internals::GeometryKey key = Internals::KeyOf(image, this->VerticalExaggeration, stride);
  // A textured surface is not reused without texturing (its texture coordinates and texture
  // would change the untextured picture).
  const bool current = in.Relief && in.Built == key && (this->Texturing || !in.Textured);
  if (!current)
  {
    in.Relief = vtkSmartPointer<vtkTerroirReliefSurface>::New();
    in.Built = Internals::GeometryKey();
    in.Textured = false;
  }
  vtkTerroirReliefSurface* relief = in.Relief;
  relief->SetInputData(image);
  relief->SetVerticalExaggeration(this->VerticalExaggeration);
  relief->SetStride(stride);
  relief->SetAmbient(this->Ambient);
  relief->SetDiffuse(this->Diffuse);
  relief->SetSpecular(this->Specular);
  relief->SetSpecularPower(this->SpecularPower);
  relief->SetParallelView(this->Mode == Map);
  relief->SetNanColor(this->NanColor);
  relief->SetBaseColor(this->BaseColor);
  if (current)
  {
    relief->ApplyAppearance();
    return relief;
  }
  if (!relief->BuildGeometry(why))
  {
    in.Relief = nullptr;
    return nullptr;
  }
  in.Built = key;
  return relief;
}

//------------------------------------------------------------------------------
vtkRenderWindow* vtkTerroirOverlayView::PrepareWindow(std::string& why)
{
  // One offscreen window for every Render() of this view while its size stays: its X
  // connection, GL context and compiled shaders are made once. The renderers of the last
  // frame are removed; each frame adds its own.
  Internals& in = *this->Internal;
  if (in.Window)
  {
    const int* size = in.Window->GetSize();
    if (size[0] != this->Width || size[1] != this->Height)
    {
      in.ReleaseWindow();
    }
  }
  if (in.Window)
  {
    vtkRendererCollection* renderers = in.Window->GetRenderers();
    while (renderers->GetNumberOfItems() > 0)
    {
      in.Window->RemoveRenderer(vtkRenderer::SafeDownCast(renderers->GetItemAsObject(0)));
    }
    return in.Window;
  }
  // VTK 9.1 aborts the process when it cannot open its X display: open it here (with retries)
  // and give it to the window, which then never opens one itself.
  void* display = terroir::rendering::OpenXDisplay(why);
  if (!display)
  {
    return nullptr;
  }
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(this->Width, this->Height);
  in.Display = display;
  window->SetDisplayId(display);
  in.Window = window;
  return window;
}

//------------------------------------------------------------------------------
bool vtkTerroirOverlayView::GetImage(vtkImageData* out)
{
  if (!out)
  {
    return this->Fail("vtkTerroirOverlayView: GetImage needs an output image");
  }
  if (!this->Render())
  {
    return false;
  }
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(this->Internal->Window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  out->DeepCopy(grab->GetOutput());
  return true;
}

bool vtkTerroirOverlayView::WritePNG(const char* fileName)
{
  if (!fileName || !*fileName)
  {
    return this->Fail("vtkTerroirOverlayView: WritePNG needs a file name");
  }
  const std::string target = fileName;
  const std::string temp = terroir::TemporaryNameFor(target);
  // Make sure the folder accepts a new file before rendering anything.
  FILE* probe = std::fopen(temp.c_str(), "wb");
  if (!probe)
  {
    const std::string why = vtksys::SystemTools::GetLastSystemError();
    terroir::DiscardTemporary(temp);
    return this->Fail("vtkTerroirOverlayView: cannot write '" + target + "': " + why);
  }
  std::fclose(probe);
  vtkNew<vtkImageData> image;
  if (!this->GetImage(image))
  {
    terroir::DiscardTemporary(temp);
    return false;
  }
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(temp.c_str());
  writer->SetInputData(image);
  writer->Write();
  if (writer->GetErrorCode() != 0)
  {
    terroir::DiscardTemporary(temp);
    return this->Fail("vtkTerroirOverlayView: writing '" + target + "' failed");
  }
  std::string error;
  if (!terroir::CommitTemporary(temp, target, error))
  {
    return this->Fail("vtkTerroirOverlayView: '" + target + "': " + error);
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkTerroirOverlayView::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ArrayName: " << (this->ArrayName ? this->ArrayName : "(none)") << "\n";
  os << indent << "ArrayComponent: " << this->ArrayComponent << "\n";
  os << indent << "Preset: " << (this->Preset ? this->Preset : "(from array)") << "\n";
  os << indent << "UseCustomRange: " << this->UseCustomRange << " Range: " << this->Range[0] << " "
     << this->Range[1] << "\n";
  os << indent << "Mode: " << (this->Mode == Map ? "Map" : "Relief") << "\n";
  os << indent << "Size: " << this->Width << " x " << this->Height << "\n";
  os << indent << "VerticalExaggeration: " << this->VerticalExaggeration << "\n";
  os << indent << "Light azimuth/elevation: " << this->LightAzimuth << " " << this->LightElevation
     << "\n";
  os << indent << "Ambient/Diffuse/Specular/Power: " << this->Ambient << " " << this->Diffuse << " "
     << this->Specular << " " << this->SpecularPower << "\n";
  os << indent << "ShowLegend: " << this->ShowLegend << "\n";
  os << indent << "Title: " << (this->Title ? this->Title : "(none)") << "\n";
  os << indent << "Texturing: " << this->Texturing << " TextureSeed: " << this->TextureSeed
     << " TexelsPerCell: " << this->TexelsPerCell << " MaxTextureSize: " << this->MaxTextureSize
     << "\n";
  os << indent << "TextureSeaLevel: " << this->TextureSeaLevel
     << " TextureSnowLine: " << this->TextureSnowLine << "\n";
}
