#include "server/testing/test_ca.hpp"

#include <fstream>
#include <stdexcept>
#include <vector>

#include "server/testing/child_process.hpp"

namespace cathbox::server::testing {

namespace {

void openssl(const std::vector<std::string>& args, const std::string& log) {
  std::vector<std::string> argv = {"/usr/bin/openssl"};  // Debian's openssl package
  argv.insert(argv.end(), args.begin(), args.end());
  ChildOptions o;
  o.stdout_file = log;
  if (run_process(argv, o) != 0) throw std::runtime_error("openssl " + args.front() + " failed (see " + log + ")");
}

}  // namespace

TestCa::TestCa(std::string folder, std::string name) : folder_(std::move(folder)), name_(std::move(name)) {
  ca_key_ = folder_ + "/" + name_ + ".key";
  ca_pem_ = folder_ + "/" + name_ + ".pem";
  openssl({"req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:P-256", "-nodes", "-keyout", ca_key_, "-out", ca_pem_,
           "-subj", "/CN=" + name_, "-days", "30"},
          folder_ + "/openssl.log");
}

TlsFiles TestCa::issue(const std::string& leaf, const std::string& san, int days) const {
  const std::string base = folder_ + "/" + leaf;
  const std::string log = folder_ + "/openssl.log";
  openssl({"req", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:P-256", "-nodes", "-keyout", base + ".key", "-out", base + ".csr",
           "-subj", "/CN=" + leaf},
          log);
  std::ofstream(base + ".ext") << "subjectAltName=" << san << "\nbasicConstraints=CA:FALSE\nextendedKeyUsage=serverAuth\n";
  openssl({"x509", "-req", "-in", base + ".csr", "-CA", ca_pem_, "-CAkey", ca_key_, "-CAcreateserial", "-out", base + ".pem", "-days",
           std::to_string(days), "-extfile", base + ".ext"},
          log);
  return TlsFiles{base + ".pem", base + ".key"};
}

}  // namespace cathbox::server::testing
