// piecewise-normals: from a segmented volume to its digital surface (and, as
// the later stages land, regularised normals, sharp features and pictures).
#include "dgBuiltinShape.h"
#include "vtkDGtalVolReader.h"
#include "vtkDigitalSurfaceFilter.h"

#include <vtkCommand.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkXMLPolyDataWriter.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

namespace
{
struct Options
{
  std::string Input;
  std::string OutputDir = ".";
  int BuiltinSize = 96;
};

void Usage()
{
  std::cout << "usage: piecewise-normals [options] [volume.vol]\n"
               "  With no volume, runs on a built-in shape (a rotated cube with a sphere and a\n"
               "  cylindrical hole), digitised on a 96^3 grid.\n"
               "  --output-dir DIR   where surface.vtp is written (default: .)\n"
               "  --size N           grid size of the built-in shape (default 96)\n"
               "  -h, --help         this help\n";
}

// Turns VTK errors into one-line messages and a failure flag.
class ErrorCatcher : public vtkCommand
{
public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* data) override
  {
    this->Failed = true;
    if (data && this->Message.empty())
    {
      this->Message = static_cast<const char*>(data);
    }
  }
  bool Failed = false;
  std::string Message;
};
} // namespace

int main(int argc, char* argv[])
{
  Options opt;
  for (int a = 1; a < argc; ++a)
  {
    const std::string arg = argv[a];
    auto value = [&]() -> std::string {
      if (a + 1 >= argc)
      {
        std::cerr << "piecewise-normals: " << arg << " needs a value\n";
        std::exit(2);
      }
      return argv[++a];
    };
    if (arg == "-h" || arg == "--help")
    {
      Usage();
      return 0;
    }
    else if (arg == "--output-dir")
    {
      opt.OutputDir = value();
    }
    else if (arg == "--size")
    {
      opt.BuiltinSize = std::atoi(value().c_str());
      if (opt.BuiltinSize < 8 || opt.BuiltinSize > 1024)
      {
        std::cerr << "piecewise-normals: --size must be in [8, 1024]\n";
        return 2;
      }
    }
    else if (!arg.empty() && arg[0] == '-')
    {
      std::cerr << "piecewise-normals: unknown option " << arg << " (see --help)\n";
      return 2;
    }
    else
    {
      opt.Input = arg;
    }
  }

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  vtkNew<ErrorCatcher> errors;
  vtkSmartPointer<vtkImageData> image;
  std::string inputName = "built-in shape";
  if (opt.Input.empty())
  {
    image = dg::MakeBuiltinShape(opt.BuiltinSize);
  }
  else
  {
    vtkNew<vtkDGtalVolReader> reader;
    reader->AddObserver(vtkCommand::ErrorEvent, errors);
    reader->SetFileName(opt.Input.c_str());
    reader->Update();
    if (errors->Failed)
    {
      std::cerr << "piecewise-normals: " << reader->GetErrorMessage() << "\n";
      return 1;
    }
    image = reader->GetOutput();
    inputName = opt.Input;
  }
  const auto t1 = Clock::now();

  vtkNew<vtkDigitalSurfaceFilter> surface;
  surface->AddObserver(vtkCommand::ErrorEvent, errors);
  surface->SetInputData(image);
  surface->Update();
  if (errors->Failed)
  {
    std::cerr << "piecewise-normals: " << errors->Message << "\n";
    return 1;
  }
  const auto t2 = Clock::now();

  const std::string path = opt.OutputDir + "/surface.vtp";
  const std::string tmp = path + ".part";
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputConnection(surface->GetOutputPort());
  writer->SetFileName(tmp.c_str());
  writer->SetDataModeToBinary(); // appended data trips Debian's expat + VTK 9.2 reader
  writer->SetCompressorTypeToZLib();
  if (!writer->Write() || std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    std::cerr << "piecewise-normals: cannot write " << path << "\n";
    return 1;
  }
  const auto t3 = Clock::now();
  auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  int dims[3];
  image->GetDimensions(dims);
  std::cout << "piecewise-normals: " << inputName << " " << dims[0] << "x" << dims[1] << "x"
            << dims[2] << " -> " << surface->GetOutput()->GetNumberOfPolys() << " surfels, "
            << surface->GetOutput()->GetNumberOfPoints() << " points -> " << path
            << " (input " << ms(t0, t1) << " ms, surface " << ms(t1, t2) << " ms, write "
            << ms(t2, t3) << " ms)\n";
  return 0;
}
