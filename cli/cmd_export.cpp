// icobrdf export SPECTRUM.h5[#MATERIAL] --format scatmech [--channel C] [--isotropic] -o FILE.csv [--json]
// icobrdf export SPECTRUM.h5[#MATERIAL] --format scatmech --wavelength-degree P [--wavelengths UM,UM,...] [--isotropic] -o FILE.csv
// icobrdf export SOURCE --format rgl|merl -o FILE [--json]
// Writes a spectrum in another program's format. Formats:
//   scatmech   coefficient file of NIST SCATMECH's ZernikeExpansion_BRDF_Model (icobrdf/io/scatmech_coefficients.hpp):
//              rows 1,1,n,m,l,l,0,a of the unpolarized element; f spectra only; an anisotropic spectrum is
//              refused unless --isotropic (then its isotropic projection is written and the dropped
//              anisotropic energy fraction reported). A 3-channel spectrum needs --channel.
//              With --wavelength-degree P (0..4): every channel is the BRDF at one wavelength (its name, like
//              "550nm", or --wavelengths in micrometres, one per channel); the coefficients are fitted by a
//              polynomial of degree P in lambda [um] and written as rows 1,1,n,m,l,l,p,a for p = 0..P
//              (icobrdf/io/scatmech_coefficients.hpp write_scatmech_polynomial); the misfit is reported.
//   rgl, merl  files renderers load from any isotropic SOURCE, read back and compared with it
//              (icobrdf/pipeline/renderer_export.hpp): RGL tensor file (Mitsuba 3, pbrt-v4), MERL table.
// The output is written atomically (nothing is written on error). Figures: rows written, order, channel,
// anisotropic energy fraction; --json prints them as JSON.
#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/scatmech_coefficients.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/renderer_export.hpp"

namespace icobrdf::cli {
namespace {

struct ExportArgs {
  std::string input, output, format;
  int channel = -1;
  int wavelength_degree = -1;
  std::vector<double> wavelengths;  // um
  bool isotropic = false, json = false;
};

void run_polynomial_export(const ExportArgs& a, const Spectrum& s) {
  if (a.channel >= 0) throw ArgumentError("export: --channel and --wavelength-degree exclude each other (every channel is a wavelength)");
  const std::vector<double> lambdas = a.wavelengths.empty() ? channel_wavelengths_um(s, "export " + a.input) : a.wavelengths;
  const ScatmechPolynomialExport e = write_scatmech_polynomial(a.output, s, lambdas, a.wavelength_degree, a.isotropic, a.input);
  nlohmann::json j = scatmech_polynomial_export_json(e, s.order, lambdas, a.wavelength_degree);
  j.update({{"input", a.input}, {"output", a.output}, {"format", a.format}});
  std::cout << (a.json ? j.dump(2) + "\n" : scatmech_polynomial_export_text(e, s.order, lambdas.size(), a.wavelength_degree, a.input, a.output));
}

void run_export(const ExportArgs& a) {
  check_output_path(a.output, {a.input});
  if (a.format != "scatmech") {
    if (a.channel >= 0 || a.wavelength_degree >= 0 || a.isotropic) throw ArgumentError("export: --channel, --wavelength-degree and --isotropic are for --format scatmech");
    const RendererExport e = export_for_renderer(a.input, a.format, a.output);
    std::cout << (a.json ? renderer_export_json(e).dump(2) + "\n" : renderer_export_text(e));
    return;
  }
  const MaterialRef ref = split_material_ref(a.input);
  const Spectrum s = read_spectrum_file(ref.path, ref.name, kScatmechModesOnly);
  if (a.wavelength_degree >= 0) return run_polynomial_export(a, s);
  if (!a.wavelengths.empty()) throw ArgumentError("export: --wavelengths needs --wavelength-degree");
  const int channel = scatmech_export_channel(s, a.channel, a.input);
  const ScatmechExport e = write_scatmech_coefficients(a.output, s, channel, a.isotropic, a.input);
  nlohmann::json j = scatmech_export_json(e, s.order, channel);
  j.update({{"input", a.input}, {"output", a.output}, {"format", a.format}});
  std::cout << (a.json ? j.dump(2) + "\n" : scatmech_export_text(e, s.order, channel, a.input, a.output));
}

void add_export_command(CLI::App& app) {
  auto a = std::make_shared<ExportArgs>();
  auto* cmd = app.add_subcommand("export", "Write a material in another program's format (SCATMECH coefficients, RGL tensor file, MERL table)");
  cmd->add_option("source", a->input, "SPECTRUM.h5[#MATERIAL] (scatmech); any SOURCE (rgl, merl)")->required();
  cmd->add_option("--format", a->format, "Output format: scatmech, rgl or merl")->required();
  cmd->add_option("--channel", a->channel, "Channel of a 3-channel spectrum (0, 1, 2)")->check(CLI::Range(0, 2));
  cmd->add_option("--wavelength-degree", a->wavelength_degree,
                  "Fit the channels, one per wavelength, by a polynomial of this degree in lambda (SCATMECH's p column)")
      ->check(CLI::Range(0, kMaxScatmechPower));
  cmd->add_option("--wavelengths", a->wavelengths, "Wavelength of each channel in micrometres (default: from channel names like 550nm)")
      ->delimiter(',');
  cmd->add_flag("--isotropic", a->isotropic, "Export the isotropic projection of an anisotropic spectrum");
  cmd->add_option("-o,--output", a->output, "Output file")->required();
  cmd->add_flag("--json", a->json, "Print the figures as JSON");
  cmd->callback([a] { run_export(*a); });
}

const CommandRegistrar kCmdExportRegistrar("export", add_export_command);

}  // namespace
}  // namespace icobrdf::cli
