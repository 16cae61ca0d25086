// A small driver, written for avs's comparison with libDAI (not part of libDAI): read a .fg
// file, run libDAI's BP with the given options, print statistics and the variable
// marginals in the UAI .MAR layout.
// usage: libdai_bp FILE.fg UPDATES TOL MAXITER DAMPING LOGDOMAIN(0/1) REPS [varmajor]
// Prints "iterations maxdiff median-seconds", then the marginals in the .MAR layout (what
// avs-concepts's bp_report example reads). Build: see docs/benchmarks/concepts.md.
#include <dai/factorgraph.h>
#include <dai/bp.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>
#include <algorithm>

using namespace dai;

// BP whose SEQFIX sequence is rebuilt variable by variable (each variable's factors in order).
struct VarMajorBP : public BP {
    VarMajorBP(const FactorGraph &fg, const PropertySet &o) : BP(fg, o) {
        _updateSeq.clear();
        for (size_t i = 0; i < nrVars(); ++i)
            for (size_t k = 0; k < nbV(i).size(); ++k)
                _updateSeq.push_back(Edge(i, k));
    }
};

int main(int argc, char **argv) {
    if (argc < 8) { fprintf(stderr, "usage\n"); return 2; }
    FactorGraph fg;
    fg.ReadFromFile(argv[1]);
    PropertySet o;
    o.set("updates", std::string(argv[2]));
    o.set("tol", (Real)atof(argv[3]));
    o.set("maxiter", (size_t)atol(argv[4]));
    o.set("damping", (Real)atof(argv[5]));
    o.set("logdomain", (bool)atoi(argv[6]));
    o.set("verbose", (size_t)0);
    int reps = atoi(argv[7]);
    bool varmajor = argc > 8 && std::string(argv[8]) == "varmajor";
    std::vector<double> times;
    std::vector<std::vector<double>> marg;
    size_t iters = 0; double md = 0;
    for (int r = 0; r < reps; ++r) {
        auto t0 = std::chrono::steady_clock::now();
        BP *bp = varmajor ? new VarMajorBP(fg, o) : new BP(fg, o);
        bp->init();
        md = bp->run();
        auto t1 = std::chrono::steady_clock::now();
        times.push_back(std::chrono::duration<double>(t1 - t0).count());
        iters = bp->Iterations();
        marg.clear();
        for (size_t i = 0; i < fg.nrVars(); ++i) {
            Factor b = bp->beliefV(i);
            std::vector<double> m;
            for (size_t s = 0; s < b.nrStates(); ++s) m.push_back(b[s]);
            marg.push_back(m);
        }
        delete bp;
    }
    std::sort(times.begin(), times.end());
    printf("%zu %.17g %.17g\n", iters, md, times[times.size() / 2]);
    printf("MAR\n%zu", marg.size());
    for (auto &m : marg) { printf(" %zu", m.size()); for (double p : m) printf(" %.17g", p); }
    printf("\n");
    return 0;
}
