#pragma once
/// \file Settings that only change how a finished run is written, never what is computed.
#include <string>

namespace kerfab {

/// Cut-sheet file formats to write (PNG previews are always written).
struct SheetFormats {
  bool svg = true;
  bool dxf = true;
  bool pdf = true;
};

/// How cut sheets draw their lines.
struct SheetStyle {
  std::string cut = "#ff0000";      ///< colour of cut lines (outlines, kerf cuts), #rrggbb
  std::string engrave = "#0000ff";  ///< colour of engraved labels, #rrggbb
  std::string mountain = "#c000c0";  ///< colour of mountain fold lines (paper), #rrggbb; drawn
                                     ///< dash-dot
  std::string valley = "#00a000";    ///< colour of valley fold lines (paper), #rrggbb; dashed
  double stroke = 0.01;             ///< line width in SVG and PDF [mm], > 0 (hairline)
};

struct OutputOptions {
  SheetFormats formats;
  SheetStyle style;
  bool dump = false;  ///< also write the intermediate stages (stages/)
};

}  // namespace kerfab
