"""Opens a solve's frames.pvd in ParaView, as a user would, and renders its last frame.

    xvfb-run -a pvbatch tools/render_in_paraview.py OUT/frames.pvd picture.png [array]

Prints the frames' times, the last frame's points and cells and every array with its range
(a check that ParaView reads what `prehensile solve` wrote); renders the last frame warped by
its displacement and coloured by `array` (default contact_pressure).
"""
import sys

from paraview.simple import (ColorBy, GetActiveCamera, GetActiveViewOrCreate,
                             GetColorTransferFunction, PVDReader, SaveScreenshot, Show,
                             WarpByVector)

pvd, picture = sys.argv[1], sys.argv[2]
array = sys.argv[3] if len(sys.argv) > 3 else 'contact_pressure'
reader = PVDReader(FileName=pvd)
reader.UpdatePipelineInformation()
times = reader.TimestepValues
print('times', list(times))
last = times[-1]
reader.UpdatePipeline(last)
info = reader.GetDataInformation()
print('points', info.GetNumberOfPoints(), 'cells', info.GetNumberOfCells())
for kind, data in (('point', reader.PointData), ('cell', reader.CellData)):
    for name in data.keys():
        a = data[name]
        print(kind, 'array', name, a.GetNumberOfComponents(), a.GetRange(-1))
warped = WarpByVector(Input=reader, Vectors=['POINTS', 'displacement'])
view = GetActiveViewOrCreate('RenderView')
view.ViewSize = [1000, 700]
view.ViewTime = last
shown = Show(warped, view)
ColorBy(shown, ('POINTS', array))
GetColorTransferFunction(array).ApplyPreset('Cool to Warm', True)
shown.SetScalarBarVisibility(view, True)
view.CameraPosition = [0.30, -0.15, 0.05]
view.CameraFocalPoint = [0.14, 0.03, -0.04]
view.CameraViewUp = [0, 0, 1]
view.ResetCamera()
GetActiveCamera().Zoom(1.3)
SaveScreenshot(picture, view, ImageResolution=[1000, 700])
print('wrote', picture)
