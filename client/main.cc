// koma: the reference client. Results on stdout, diagnostics on stderr.
// Exit codes: 0 ok, 1 failure (RPC error, bad file), 2 usage error. See docs/usage.md.
#include "client/batch/batch_command.h"
#include "client/cli.h"

int main(int argc, char** argv) {
  if (const int code = koma::client::batch::RunIfBatch(argc, argv); code >= 0) return code;
  return koma::client::KomaMain(argc, argv);
}
