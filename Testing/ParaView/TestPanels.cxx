// The plugin's panels and help pages as a ParaView GUI user meets them
// (issue 40), in a real Qt application on its own X display: for each
// filter and reader, the Properties panel that ParaView builds
// (pqProxyWidget) renders (a screenshot with content, saved to DG_TEST_TMP),
// shows its property groups, hides its advanced properties until the gear
// button asks for them, and the filter's help page (XML_DOCUMENTATION) is
// found by the help engine the way the panel's "?" button looks it up and
// holds the filter's documentation.
#include <pqApplicationCore.h>
#include <pqObjectBuilder.h>
#include <pqPluginDocumentationBehavior.h>
#include <pqProxyWidget.h>
#include <pqServerResource.h>
#include <vtkSMPluginManager.h>
#include <vtkSMProxy.h>
#include <vtkSMProxyManager.h>
#include <vtkSMSessionProxyManager.h>
#include <vtkSmartPointer.h>

#include <QApplication>
#include <QFileInfo>
#include <QHelpEngine>
#include <QImage>
#include <QLabel>
#include <QSet>
#include <QUrl>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace
{
int Failures = 0;

void Check(bool ok, const std::string& what)
{
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
  Failures += ok ? 0 : 1;
}

struct Panel
{
  const char* Group;
  const char* Name;
  std::vector<const char*> GroupLabels;    // PropertyGroup labels shown by default
  std::vector<const char*> AdvancedGroups; // groups of advanced properties only
  const char* Basic;                    // a property label always shown
  const char* Advanced;                 // a property label behind the gear button
  const char* HelpText;                 // a phrase of the proxy's documentation
  bool Empty = false; // nothing to set by default (a reader's file name, a default array)
};

// A label is shown when the panel would draw it; group headers and property
// labels are QLabels whose text may carry markup.
bool Shows(QWidget& panel, const QString& text)
{
  for (QLabel* label : panel.findChildren<QLabel*>())
  {
    if (label->isVisibleTo(&panel) && label->text().contains(text))
    {
      return true;
    }
  }
  return false;
}

// Distinct colours of the screenshot: an empty or failed panel is one or
// two flat colours; text and widgets give hundreds.
int DistinctColours(const QImage& image)
{
  QSet<QRgb> colours;
  for (int y = 0; y < image.height(); y += 2)
  {
    for (int x = 0; x < image.width(); x += 2)
    {
      colours.insert(image.pixel(x, y));
    }
  }
  return colours.size();
}

QByteArray HelpPage(QHelpEngine* engine, const QString& group, const QString& name)
{
  // The URL pqHelpReaction::showProxyHelp builds from the panel's "?" button.
  for (const QString& ns : engine->registeredDocumentations())
  {
    const QString url = QString("qthelp://%1/%2/%3.%4.html")
                          .arg(ns, QFileInfo(ns).baseName(), group, name);
    QByteArray data = engine->fileData(QUrl(url));
    if (!data.isEmpty())
    {
      return data;
    }
  }
  return QByteArray();
}
} // namespace

int main(int argc, char** argv)
{
  const char* plugin = std::getenv("DG_PLUGIN_FILE");
  const char* tmp = std::getenv("DG_TEST_TMP");
  if (!plugin || !tmp)
  {
    std::fprintf(stderr, "TestPanels: set DG_PLUGIN_FILE and DG_TEST_TMP\n");
    return 2;
  }
  QApplication app(argc, argv);
  // --dr: no user settings read or written, so that runs do not depend on
  // each other or on the machine's ParaView settings.
  int pvArgc = 2;
  char arg0[] = "TestPanels";
  char arg1[] = "--dr";
  char* pvArgv[] = { arg0, arg1, nullptr };
  pqApplicationCore core(pvArgc, pvArgv);
  pqServer* server = core.getObjectBuilder()->createServer(pqServerResource("builtin:"));
  Check(server != nullptr, "builtin server");
  QHelpEngine* engine = core.helpEngine();
  new pqPluginDocumentationBehavior(engine);

  vtkSMProxyManager* manager = vtkSMProxyManager::GetProxyManager();
  Check(manager->GetPluginManager()->LoadLocalPlugin(plugin), std::string("plugin loads: ") + plugin);
  app.processEvents();
  vtkSMSessionProxyManager* pxm = manager->GetActiveSessionProxyManager();

  const std::vector<Panel> panels = {
    { "filters", "AmbrosioTortorelli", { "Field", "Energy", "Schedule" }, { "Solver" }, "Lambda",
      "Solver Tolerance", "Ambrosio-Tortorelli" },
    { "filters", "SharpFeatures", { "Input", "Band and Regions", "Feature Lines" },
      { "Band Sides", "Output Field" }, "Minimum Feature Angle", "Quadric Merge Factor",
      "feature line" },
    { "filters", "CorrectedCurvature", {}, {}, "Radius Units", "Regions", "each side of a crease" },
    { "filters", "PiecewiseSmoothMesh", {}, {}, "Normals", "Data Weight", "voxel corner" },
    { "filters", "DigitalSurface", {}, {}, "Selection Mode", "", "" },
    { "filters", "IINormalEstimator", {}, {}, "Radius", "", "" },
    { "filters", "VCMNormalEstimator", {}, {}, "", "", "" },
    { "filters", "RHTNormalEstimator", {}, {}, "", "", "" },
    { "filters", "DigitalIslands", {}, {}, "", "", "" },
    { "filters", "DigitalNoise", {}, {}, "", "", "" },
    { "filters", "SplitByLabel", {}, {}, "", "", "", true },
    { "sources", "DGtalVolReader", {}, {}, "", "", "", true },
    { "sources", "NIfTIVolumeReader", {}, {}, "", "", "" },
    { "sources", "OrientedImageReader", {}, {}, "", "", "" },
  };
  for (const Panel& p : panels)
  {
    const std::string id = p.Name;
    vtkSmartPointer<vtkSMProxy> proxy;
    proxy.TakeReference(pxm->NewProxy(p.Group, p.Name));
    Check(proxy != nullptr, id + ": proxy");
    if (!proxy)
    {
      continue;
    }
    pqProxyWidget panel(proxy);
    panel.filterWidgets(false);
    panel.show();
    app.processEvents();
    panel.resize(480, std::max(100, panel.sizeHint().height()));
    app.processEvents();
    const QImage shot = panel.grab().toImage();
    const QString file = QString("%1/panel_%2.png").arg(tmp, p.Name);
    Check(shot.save(file), id + ": screenshot saved to " + file.toStdString());
    const int colours = DistinctColours(shot);
    if (!p.Empty)
    {
      Check(colours > 50, id + ": panel has content (" + std::to_string(colours) + " colours)");
    }
    for (const char* g : p.GroupLabels)
    {
      Check(Shows(panel, g), id + ": group '" + g + "' shown");
    }
    for (const char* g : p.AdvancedGroups)
    {
      Check(!Shows(panel, g), id + ": group '" + g + "' hidden by default");
    }
    if (*p.Basic)
    {
      Check(Shows(panel, p.Basic), id + ": '" + p.Basic + "' shown by default");
    }
    if (*p.Advanced)
    {
      Check(!Shows(panel, p.Advanced), id + ": '" + p.Advanced + "' hidden by default");
      panel.filterWidgets(true);
      app.processEvents();
      Check(Shows(panel, p.Advanced), id + ": '" + p.Advanced + "' shown with advanced");
      for (const char* g : p.AdvancedGroups)
      {
        Check(Shows(panel, g), id + ": group '" + g + "' shown with advanced");
      }
      const QString advancedFile = QString("%1/panel_%2_advanced.png").arg(tmp, p.Name);
      panel.resize(480, std::max(100, panel.sizeHint().height()));
      app.processEvents();
      Check(panel.grab().toImage().save(advancedFile), id + ": advanced screenshot saved");
    }
    const QByteArray help = HelpPage(engine, p.Group, p.Name);
    Check(!help.isEmpty(), id + ": help page found (" + std::to_string(help.size()) + " bytes)");
    if (*p.HelpText)
    {
      Check(help.contains(p.HelpText), id + ": help page holds '" + p.HelpText + "'");
    }
    panel.hide();
  }
  std::printf("%d failure(s)\n", Failures);
  return Failures == 0 ? 0 : 1;
}
