#include "vtkTerroirOverlayView.h"

#include "TerroirSafeOutput.h"

#include "vtkActor.h"
#include "vtkActor2D.h"
#include "vtkAutoInit.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCoordinate.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
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
#include "vtkScalarBarActor.h"
#include "vtkShaderProperty.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirColorPresets.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirXDisplay.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
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
#include <vector>

#include <unistd.h>

// Register the OpenGL render window and FreeType text factories whenever this library is
// loaded, so that C++ programs and Python scripts need no vtk_module_autoinit of their own.
VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingFreeType);

vtkStandardNewMacro(vtkTerroirOverlayView);

namespace
{
// Blinn-Phong lighting, appended after VTK's own light code (which uses Phong's reflection
// vector) and overwriting its result. Uses VTK's declarations for lighting complexity 2 (one
// directional scene light): normalVCVSOutput, vertexVC, lightDirectionVC0, lightColor0,
// ambientColor/diffuseColor (= coefficient x vertex colour), specularColor, specularPower.
const char* BlinnPhongImpl = R"(//VTK::Light::Impl
  {
    vec3 tN = normalize(normalVCVSOutput);
    vec3 tL = normalize(-lightDirectionVC0);
    vec3 tV = (terroirParallel != 0) ? vec3(0.0, 0.0, 1.0) : normalize(-vertexVC.xyz);
    vec3 tH = normalize(tL + tV);
    float tDf = max(0.0, dot(tN, tL));
    float tSf = (tDf > 0.0) ? pow(max(0.0, dot(tN, tH)), specularPower) : 0.0;
    gl_FragData[0] = vec4(ambientColor + tDf * lightColor0 * diffuseColor +
      tSf * lightColor0 * specularColor, opacity);
  }
)";
}

struct vtkTerroirOverlayView::Internals
{
  vtkSmartPointer<vtkImageData> Input;
  vtkSmartPointer<vtkRenderWindow> Window;
  void* Display = nullptr; // X11 Display* owned by us, used by Window

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
  ~Internals() { this->ReleaseWindow(); }
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
bool vtkTerroirOverlayView::Render()
{
  this->LastError.clear();
  this->Internal->ReleaseWindow();

  // ---- validate the input -------------------------------------------------------------
  vtkImageData* image = this->Internal->Input;
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
  vtkDataArray* values = pd->GetArray(arrayName);
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
  const char* preset = this->GetEffectivePreset();
  if (!vtkTerroirColorPresets::HasPreset(preset))
  {
    return this->Fail(std::string("vtkTerroirOverlayView: unknown colour preset '") + preset + "'");
  }
  vtkDataArray* mask = pd->GetArray(vtkTerroirGeoreference::ValidMaskName());

  // ---- points, validity, normals -------------------------------------------------------
  const int nx = dims[0];
  const int ny = dims[1];
  const vtkIdType n = static_cast<vtkIdType>(nx) * ny;
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  const double ve = this->VerticalExaggeration;

  std::vector<unsigned char> valid(n);
  std::vector<double> z(n);
  double zFill = std::numeric_limits<double>::infinity();
  double zMax = -std::numeric_limits<double>::infinity();
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double e = elevation->GetComponent(k, 0);
    const bool ok = std::isfinite(e) && (!mask || mask->GetComponent(k, 0) != 0.0);
    valid[k] = ok ? 1 : 0;
    z[k] = e * ve;
    if (ok)
    {
      zFill = std::min(zFill, z[k]);
      zMax = std::max(zMax, z[k]);
    }
  }
  if (!std::isfinite(zFill))
  {
    return this->Fail("vtkTerroirOverlayView: the terrain has no valid elevation");
  }
  for (vtkIdType k = 0; k < n; ++k)
  {
    if (!valid[k])
    {
      z[k] = zFill;
    }
  }

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(n);
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * nx + i;
      points->SetPoint(k, origin[0] + i * spacing[0], origin[1] + j * spacing[1], z[k]);
      // Central differences where both neighbours are valid, else one-sided, else flat.
      auto derivative =
        [&](vtkIdType kMinus, bool hasMinus, vtkIdType kPlus, bool hasPlus, double h) -> double
      {
        hasMinus = hasMinus && valid[kMinus];
        hasPlus = hasPlus && valid[kPlus];
        if (!valid[k])
        {
          return 0.0;
        }
        if (hasMinus && hasPlus)
        {
          return (z[kPlus] - z[kMinus]) / (2.0 * h);
        }
        if (hasPlus)
        {
          return (z[kPlus] - z[k]) / h;
        }
        if (hasMinus)
        {
          return (z[k] - z[kMinus]) / h;
        }
        return 0.0;
      };
      const double dzdx = derivative(k - 1, i > 0, k + 1, i < nx - 1, spacing[0]);
      const double dzdy = derivative(k - nx, j > 0, k + nx, j < ny - 1, spacing[1]);
      double nrm[3] = { -dzdx, -dzdy, 1.0 };
      vtkMath::Normalize(nrm);
      normals->SetTuple(k, nrm);
    }
  }

  // ---- colours ---------------------------------------------------------------------------
  const int comp = this->ArrayComponent;
  // A preset's mask array (WaterBodies: WaterBody) leaves its zero cells uncoloured.
  const char* maskName = vtkTerroirColorPresets::GetMaskArrayName(preset);
  vtkDataArray* bodyMask = maskName ? pd->GetArray(maskName) : nullptr;
  if (bodyMask && (bodyMask->GetNumberOfComponents() != 1 || bodyMask->GetNumberOfTuples() != n))
  {
    bodyMask = nullptr;
  }
  auto coloured = [bodyMask](vtkIdType k)
  { return !bodyMask || bodyMask->GetComponent(k, 0) != 0.0; };
  double range[2];
  if (this->UseCustomRange)
  {
    range[0] = this->Range[0];
    range[1] = this->Range[1];
  }
  else if (!vtkTerroirColorPresets::GetDefaultRange(preset, range))
  {
    range[0] = std::numeric_limits<double>::infinity();
    range[1] = -std::numeric_limits<double>::infinity();
    for (vtkIdType k = 0; k < n; ++k)
    {
      const double v = values->GetComponent(k, comp);
      if (valid[k] && std::isfinite(v) && coloured(k))
      {
        range[0] = std::min(range[0], v);
        range[1] = std::max(range[1], v);
      }
    }
    if (!std::isfinite(range[0]))
    {
      range[0] = 0.0;
      range[1] = 1.0;
    }
  }
  vtkNew<vtkLookupTable> lut;
  if (!vtkTerroirColorPresets::ConfigureLookupTable(lut, preset, range[0], range[1]))
  {
    return this->Fail("vtkTerroirOverlayView: invalid colour range [" + std::to_string(range[0]) +
      ", " + std::to_string(range[1]) + "]");
  }
  lut->SetNanColor(this->NanColor);
  // Clusters from vtkTerroirKMeans: each zone's share of the cells (field data
  // KMeansClusterShare, one fraction per cluster id) goes into its legend label, "i: p%", under
  // the title "Cluster (share)" (short enough for the legend column at 400 pixels).
  vtkDataArray* shares = std::strcmp(preset, "Clusters") == 0
    ? image->GetFieldData()->GetArray("KMeansClusterShare")
    : nullptr;
  std::string categoricalTitle = vtkTerroirColorPresets::GetTitle(preset);
  if (shares && shares->GetNumberOfComponents() == 1)
  {
    categoricalTitle = "Cluster (share)";
    for (vtkIdType k = 0; k < lut->GetNumberOfAnnotatedValues(); ++k)
    {
      const vtkIdType id = lut->GetAnnotatedValue(k).ToInt();
      if (id >= 0 && id < shares->GetNumberOfTuples())
      {
        char label[64];
        std::snprintf(
          label, sizeof(label), "%d: %.0f%%", static_cast<int>(id), 100.0 * shares->GetTuple1(id));
        lut->SetAnnotation(lut->GetAnnotatedValue(k), label);
      }
    }
  }
  this->LastRange[0] = range[0];
  this->LastRange[1] = range[1];

  vtkNew<vtkUnsignedCharArray> colors;
  colors->SetName("OverlayColors");
  colors->SetNumberOfComponents(3);
  colors->SetNumberOfTuples(n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double v = values->GetComponent(k, comp);
    const unsigned char* rgba = lut->MapValue(v);
    const double a = coloured(k) ? rgba[3] / 255.0 : 0.0;
    unsigned char out[3];
    for (int c = 0; c < 3; ++c)
    {
      const double blended = a * rgba[c] + (1.0 - a) * 255.0 * this->BaseColor[c];
      out[c] = static_cast<unsigned char>(std::lround(std::min(255.0, std::max(0.0, blended))));
    }
    colors->SetTypedTuple(k, out);
  }

  // ---- cells: valid quads are shaded, the others drawn flat in the NaN colour ------------
  vtkNew<vtkCellArray> surfaceCells;
  vtkNew<vtkCellArray> holeCells;
  for (int j = 0; j + 1 < ny; ++j)
  {
    for (int i = 0; i + 1 < nx; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * nx + i;
      const vtkIdType quad[4] = { k, k + 1, k + 1 + nx, k + nx };
      const bool ok = valid[quad[0]] && valid[quad[1]] && valid[quad[2]] && valid[quad[3]];
      (ok ? surfaceCells : holeCells)->InsertNextCell(4, quad);
    }
  }

  vtkNew<vtkPolyData> surface;
  surface->SetPoints(points);
  surface->SetPolys(surfaceCells);
  surface->GetPointData()->SetNormals(normals);
  surface->GetPointData()->SetScalars(colors);

  vtkNew<vtkPolyData> holes;
  holes->SetPoints(points);
  holes->SetPolys(holeCells);

  const bool parallel = this->Mode == Map;

  vtkNew<vtkPolyDataMapper> surfaceMapper;
  surfaceMapper->SetInputData(surface);
  surfaceMapper->SetColorModeToDirectScalars();
  surfaceMapper->SetScalarModeToUsePointData();
  surfaceMapper->ScalarVisibilityOn();
  vtkNew<vtkActor> surfaceActor;
  surfaceActor->SetMapper(surfaceMapper);
  vtkProperty* prop = surfaceActor->GetProperty();
  prop->SetInterpolationToPhong();
  prop->SetAmbient(this->Ambient);
  prop->SetDiffuse(this->Diffuse);
  prop->SetSpecular(this->Specular);
  prop->SetSpecularPower(this->SpecularPower);
  prop->SetSpecularColor(1.0, 1.0, 1.0);
  vtkShaderProperty* shaderProp = surfaceActor->GetShaderProperty();
  shaderProp->AddFragmentShaderReplacement("//VTK::Light::Impl", false, BlinnPhongImpl, false);
  shaderProp->GetFragmentCustomUniforms()->SetUniformi("terroirParallel", parallel ? 1 : 0);

  vtkNew<vtkPolyDataMapper> holeMapper;
  holeMapper->SetInputData(holes);
  holeMapper->ScalarVisibilityOff();
  vtkNew<vtkActor> holeActor;
  holeActor->SetMapper(holeMapper);
  holeActor->GetProperty()->LightingOff();
  holeActor->GetProperty()->SetColor(this->NanColor[0], this->NanColor[1], this->NanColor[2]);
  holeActor->GetProperty()->SetOpacity(this->NanColor[3]);
  holeActor->SetVisibility(holeCells->GetNumberOfCells() > 0 && this->NanColor[3] > 0.0);

  // ---- renderers and light ---------------------------------------------------------------
  // Layout: the legend takes the right quarter, the title a strip at the top (8% of the
  // height, at least 24 pixels); the terrain gets the rest.
  const double legendWidth = this->ShowLegend ? 0.25 : 0.0;
  const bool hasTitle = this->Title && *this->Title;
  const double titleHeight = hasTitle ? std::max(0.08, 24.0 / this->Height) : 0.0;
  vtkNew<vtkRenderer> renderer;
  renderer->SetViewport(0.0, 0.0, 1.0 - legendWidth, 1.0 - titleHeight);
  renderer->SetBackground(this->Background);
  renderer->AutomaticLightCreationOff();
  renderer->AddActor(surfaceActor);
  renderer->AddActor(holeActor);

  double bounds[6];
  bounds[0] = origin[0];
  bounds[1] = origin[0] + (nx - 1) * spacing[0];
  bounds[2] = origin[1];
  bounds[3] = origin[1] + (ny - 1) * spacing[1];
  bounds[4] = zFill;
  bounds[5] = zMax;
  const double center[3] = {
    0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5])
  };
  const double sizeX = std::abs(bounds[1] - bounds[0]);
  const double sizeY = std::abs(bounds[3] - bounds[2]);
  const double sizeZ = bounds[5] - bounds[4];
  const double radius = 0.5 * std::sqrt(sizeX * sizeX + sizeY * sizeY + sizeZ * sizeZ);
  const double aspect = ((1.0 - legendWidth) * this->Width) / ((1.0 - titleHeight) * this->Height);

  const double az = vtkMath::RadiansFromDegrees(this->LightAzimuth);
  const double el = vtkMath::RadiansFromDegrees(this->LightElevation);
  const double toLight[3] = {
    std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el)
  };
  vtkNew<vtkLight> light;
  light->SetLightTypeToSceneLight();
  light->PositionalOff();
  light->SetColor(1.0, 1.0, 1.0);
  light->SetIntensity(1.0);
  light->SetFocalPoint(center[0], center[1], center[2]);
  light->SetPosition(center[0] + toLight[0] * 10.0 * radius,
    center[1] + toLight[1] * 10.0 * radius,
    center[2] + toLight[2] * 10.0 * radius);
  renderer->AddLight(light);

  vtkCamera* camera = renderer->GetActiveCamera();
  if (parallel)
  {
    camera->ParallelProjectionOn();
    camera->SetFocalPoint(center[0], center[1], center[2]);
    camera->SetPosition(center[0], center[1], bounds[5] + 2.0 * radius + 1.0);
    camera->SetViewUp(0.0, 1.0, 0.0);
    camera->SetParallelScale(std::max(0.5 * sizeY, 0.5 * sizeX / aspect));
  }
  else
  {
    // Fixed direction; the distance is the smallest one at which all 8 corners of the bounding
    // box project inside the frame (tighter than fitting the bounding sphere).
    const double viewAngle = GetReliefViewAngle();
    const double caz = vtkMath::RadiansFromDegrees(GetReliefCameraAzimuth());
    const double cel = vtkMath::RadiansFromDegrees(GetReliefCameraElevation());
    const double tanV = std::tan(vtkMath::RadiansFromDegrees(0.5 * viewAngle));
    const double tanH = tanV * aspect;
    // Unit vectors: toward the camera (back), screen right and screen up.
    const double back[3] = {
      std::sin(caz) * std::cos(cel), std::cos(caz) * std::cos(cel), std::sin(cel)
    };
    double right[3];
    const double zUp[3] = { 0.0, 0.0, 1.0 };
    vtkMath::Cross(zUp, back, right);
    vtkMath::Normalize(right);
    double up[3];
    vtkMath::Cross(back, right, up);
    double distance = 0.0;
    for (int corner = 0; corner < 8; ++corner)
    {
      const double p[3] = { bounds[corner & 1] - center[0],
        bounds[2 + ((corner >> 1) & 1)] - center[1],
        bounds[4 + ((corner >> 2) & 1)] - center[2] };
      const double w = vtkMath::Dot(p, back);
      distance = std::max(distance, w + std::abs(vtkMath::Dot(p, right)) / tanH);
      distance = std::max(distance, w + std::abs(vtkMath::Dot(p, up)) / tanV);
    }
    distance = std::max(distance * 1.03, 1e-6 + radius * 0.1);
    camera->ParallelProjectionOff();
    camera->SetViewAngle(viewAngle);
    camera->SetFocalPoint(center[0], center[1], center[2]);
    camera->SetPosition(center[0] + distance * back[0],
      center[1] + distance * back[1],
      center[2] + distance * back[2]);
    camera->SetViewUp(0.0, 0.0, 1.0);
  }
  renderer->ResetCameraClippingRange(bounds);

  const double luminance =
    0.2126 * this->Background[0] + 0.7152 * this->Background[1] + 0.0722 * this->Background[2];
  const double textGrey = luminance > 0.5 ? 0.0 : 1.0;

  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0);
  window->SetSize(this->Width, this->Height);
  window->AddRenderer(renderer);

  if (hasTitle)
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

  if (this->ShowLegend)
  {
    vtkNew<vtkRenderer> legendRenderer;
    legendRenderer->SetViewport(1.0 - legendWidth, 0.0, 1.0, 1.0 - titleHeight);
    legendRenderer->SetBackground(this->Background);
    const int fontSize = std::max(8, this->Height / 36);
    if (vtkTerroirColorPresets::IsCategorical(preset))
    {
      this->AddCategoricalLegend(legendRenderer, lut, categoricalTitle, fontSize, textGrey);
    }
    else
    {
      this->AddScalarBar(legendRenderer, lut, preset, fontSize, textGrey);
    }
    window->AddRenderer(legendRenderer);
  }

  // VTK 9.1 aborts the process when it cannot open its X display: open it here (with retries)
  // and give it to the window, which then never opens one itself.
  std::string why;
  void* display = terroir::rendering::OpenXDisplay(why);
  if (!display)
  {
    return this->Fail("vtkTerroirOverlayView: " + why);
  }
  this->Internal->Display = display;
  window->SetDisplayId(display);
  window->Render();
  this->Internal->Window = window;
  return true;
}

//------------------------------------------------------------------------------
void vtkTerroirOverlayView::AddScalarBar(vtkRenderer* legendRenderer,
  vtkLookupTable* lut,
  const char* preset,
  int fontSize,
  double grey)
{
  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(lut);
  // Title on two lines ("Temperature" / "(°C)") so that it fits the narrow legend column.
  std::string legendTitle = vtkTerroirColorPresets::GetTitle(preset);
  const std::string units = vtkTerroirColorPresets::GetUnits(preset);
  if (!units.empty())
  {
    legendTitle += "\n(" + units + ")";
  }
  bar->SetTitle(legendTitle.c_str());
  bar->SetNumberOfLabels(5);
  // Large values (insolation in Wh/m²/day, elevations in m) as whole numbers, not "7.76e+03".
  const double* tableRange = lut->GetTableRange();
  if (std::max(std::fabs(tableRange[0]), std::fabs(tableRange[1])) >= 1000.0)
  {
    bar->SetLabelFormat("%-6.0f");
  }
  bar->SetMaximumNumberOfColors(256);
  bar->SetDrawNanAnnotation(0);
  bar->SetDrawAnnotations(0);
  bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  bar->SetPosition(0.04, 0.06);
  bar->SetWidth(0.92);
  bar->SetHeight(0.80);
  bar->SetBarRatio(0.22);
  bar->SetTextPositionToSucceedScalarBar(); // labels right of the bar
  bar->UnconstrainedFontSizeOn();
  for (vtkTextProperty* tp : { bar->GetTitleTextProperty(), bar->GetLabelTextProperty() })
  {
    tp->SetColor(grey, grey, grey);
    tp->ShadowOff();
    tp->ItalicOff();
    tp->BoldOff();
    tp->SetFontSize(fontSize);
  }
  bar->GetTitleTextProperty()->BoldOn();
  legendRenderer->AddActor2D(bar);
}

//------------------------------------------------------------------------------
void vtkTerroirOverlayView::AddCategoricalLegend(vtkRenderer* legendRenderer,
  vtkLookupTable* lut,
  const std::string& titleText,
  int fontSize,
  double grey)
{
  // One swatch and name per annotated value, top to bottom, under the title.
  vtkNew<vtkTextActor> title;
  title->SetInput(titleText.c_str());
  title->GetTextProperty()->SetFontSize(fontSize);
  title->GetTextProperty()->SetColor(grey, grey, grey);
  title->GetTextProperty()->BoldOn();
  title->GetTextProperty()->SetVerticalJustificationToTop();
  title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  title->SetPosition(0.08, 0.94);
  legendRenderer->AddActor2D(title);

  const vtkIdType n = lut->GetNumberOfAnnotatedValues();
  const double rowHeight = std::min(0.07, 0.84 / std::max<vtkIdType>(n, 1));
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double top = 0.88 - k * rowHeight;
    const double bottom = top - 0.75 * rowHeight;
    vtkNew<vtkPoints> corners;
    corners->InsertNextPoint(0.08, bottom, 0.0);
    corners->InsertNextPoint(0.28, bottom, 0.0);
    corners->InsertNextPoint(0.28, top, 0.0);
    corners->InsertNextPoint(0.08, top, 0.0);
    vtkNew<vtkCellArray> quad;
    const vtkIdType ids[4] = { 0, 1, 2, 3 };
    quad->InsertNextCell(4, ids);
    vtkNew<vtkPolyData> swatchData;
    swatchData->SetPoints(corners);
    swatchData->SetPolys(quad);
    vtkNew<vtkCoordinate> normalized;
    normalized->SetCoordinateSystemToNormalizedViewport();
    vtkNew<vtkPolyDataMapper2D> swatchMapper;
    swatchMapper->SetInputData(swatchData);
    swatchMapper->SetTransformCoordinate(normalized);
    vtkNew<vtkActor2D> swatch;
    swatch->SetMapper(swatchMapper);
    const unsigned char* rgba = lut->MapValue(lut->GetAnnotatedValue(k).ToDouble());
    const double rgb[3] = { rgba[0] / 255.0, rgba[1] / 255.0, rgba[2] / 255.0 };
    swatch->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
    legendRenderer->AddActor2D(swatch);
    // A swatch in (nearly) the background colour, such as Sunlit's white "lit" on the white
    // background, gets an outline in the text colour so that it can be seen.
    const double contrast = std::fabs(rgb[0] - this->Background[0]) +
      std::fabs(rgb[1] - this->Background[1]) + std::fabs(rgb[2] - this->Background[2]);
    if (contrast < 0.3)
    {
      vtkNew<vtkCellArray> loop;
      const vtkIdType ring[5] = { 0, 1, 2, 3, 0 };
      loop->InsertNextCell(5, ring);
      vtkNew<vtkPolyData> outlineData;
      outlineData->SetPoints(corners);
      outlineData->SetLines(loop);
      vtkNew<vtkPolyDataMapper2D> outlineMapper;
      outlineMapper->SetInputData(outlineData);
      outlineMapper->SetTransformCoordinate(normalized);
      vtkNew<vtkActor2D> outline;
      outline->SetMapper(outlineMapper);
      outline->GetProperty()->SetColor(grey, grey, grey);
      outline->GetProperty()->SetLineWidth(1.0f);
      legendRenderer->AddActor2D(outline);
    }

    vtkNew<vtkTextActor> label;
    label->SetInput(lut->GetAnnotation(k).c_str());
    label->GetTextProperty()->SetFontSize(fontSize);
    label->GetTextProperty()->SetColor(grey, grey, grey);
    label->GetTextProperty()->SetVerticalJustificationToCentered();
    label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    label->SetPosition(0.34, 0.5 * (top + bottom));
    legendRenderer->AddActor2D(label);
  }
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
}
