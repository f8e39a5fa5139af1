// `gaitforge plot ID`: figures of a study as image files, drawn by matplotlib through
// clients/python/gaitforge_plot.py.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "clients/cli/cli.h"
#include "services/core/subprocess.h"

namespace gaitforge::cli {
namespace {

std::string PlotScript() {
  if (const char* s = std::getenv("GAITFORGE_PLOT_SCRIPT")) return s;
  return core::PythonScript("gaitforge_plot.py");
}

using core::Python;

}  // namespace

std::string PlotScriptPath() { return PlotScript(); }

int RunPlotScript(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {Python(), PlotScript()};
  argv.insert(argv.end(), args.begin(), args.end());
  pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> a;
    for (auto& s : argv) a.push_back(s.data());
    a.push_back(nullptr);
    if (int devnull = open("/dev/null", O_WRONLY); devnull >= 0) dup2(devnull, STDOUT_FILENO);
    execv(a[0], a.data());
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
}

int PlotStudy(v1::StudyService::Stub& stub, const std::string& id, const std::string& out_dir,
              const GlobalOptions& g, std::vector<std::string>* written) {
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetHistoryRequest req;
  req.set_study_id(id);
  v1::GetHistoryResponse resp;
  grpc::Status s = stub.GetHistory(&ctx, req, &resp);
  if (!s.ok()) return ReportRpcError(s, "plot " + id);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  const std::string json = out_dir + "/" + id + "-history.json";
  std::ofstream(json) << ToJson(resp) << "\n";
  const std::string svg = out_dir + "/" + id + "-fitness.svg";
  if (RunPlotScript({"fitness", "--history", json, "--out", svg, "--title", id}) != 0) {
    std::cerr << "gaitforge: plotting failed (needs " << Python()
              << " with python3-matplotlib; script " << PlotScript() << ")\n";
    return kFailed;
  }
  written->push_back(svg);
  return kOk;
}

int CmdPlot(const GlobalOptions& g, const std::vector<std::string>& args,
            const std::string& out_dir) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge plot STUDY_ID [--out DIR]\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  std::vector<std::string> written;
  code = PlotStudy(conn->study(), args[0], out_dir, g, &written);
  for (const auto& f : written) std::cout << f << "\n";
  return code;
}

}  // namespace gaitforge::cli
