// koma: the reference client. Results on stdout, diagnostics on stderr.
// Exit codes: 0 ok, 1 failure (RPC error, bad file), 2 usage error. See docs/usage.md.
#include "client/cli.h"

int main(int argc, char** argv) { return koma::client::KomaMain(argc, argv); }
