// The program's default input: a shape with sharp and smooth features (a
// rotated cube, united with a sphere and cut by a cylinder), digitised.
#ifndef dgBuiltinShape_h
#define dgBuiltinShape_h

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

namespace dg
{
/// An n^3 unsigned char image (1 inside, 0 outside), spacing 1, origin 0.
vtkSmartPointer<vtkImageData> MakeBuiltinShape(int n);
}

#endif
