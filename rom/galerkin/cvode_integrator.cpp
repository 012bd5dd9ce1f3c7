// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/galerkin/cvode_integrator.hpp"

#include <exception>
#include <stdexcept>
#include <string>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

namespace mixload::rom {

struct CvodeIntegrator::State {
    SUNContext ctx = nullptr;
    N_Vector y = nullptr, atol = nullptr;
    SUNMatrix A = nullptr;
    SUNLinearSolver ls = nullptr;
    void* mem = nullptr;
    Rhs rhs;
    Jacobian jacobian;
    Eigen::MatrixXd jacOut;
    Eigen::Index n = 0;
    bool started = false;
    // CVodeReInit resets CVODE's counters: the totals of earlier restarts, and the current one's.
    long steps = 0, rhsEvals = 0, jacs = 0, stepsSinceRestart = 0, rhsSinceRestart = 0, jacsSinceRestart = 0;
    Eigen::VectorXd yIn, dyOut;
    std::exception_ptr error;

    static int f(sunrealtype t, N_Vector y, N_Vector dy, void* user) {
        auto* s = static_cast<State*>(user);
        try {
            s->yIn = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(y), s->n);
            s->rhs(t, s->yIn, s->dyOut);
            if (!s->dyOut.allFinite()) return 1;  // recoverable: CVODE retries with a smaller step
            Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(dy), s->n) = s->dyOut;
            return 0;
        } catch (...) {
            s->error = std::current_exception();
            return -1;
        }
    }

    static int jac(sunrealtype t, N_Vector y, N_Vector, SUNMatrix J, void* user, N_Vector, N_Vector, N_Vector) {
        auto* s = static_cast<State*>(user);
        try {
            s->yIn = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(y), s->n);
            s->jacobian(t, s->yIn, s->jacOut);
            if (!s->jacOut.allFinite()) return 1;
            // SUNDIALS' dense matrix is column-major with leading dimension n, as Eigen's default.
            Eigen::Map<Eigen::MatrixXd>(SUNDenseMatrix_Data(J), s->n, s->n) = s->jacOut;
            return 0;
        } catch (...) {
            s->error = std::current_exception();
            return -1;
        }
    }
};

namespace {
void check(int flag, const char* what) {
    if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + what + " failed: " + CVodeGetReturnFlagName(flag));
}
}  // namespace

CvodeIntegrator::CvodeIntegrator(Eigen::Index n, Rhs rhs, double rtol, const Eigen::VectorXd& atol)
    : s_(std::make_unique<State>()) {
    if (n <= 0 || atol.size() != n) throw std::invalid_argument("CVODE integrator: state size and tolerances differ");
    s_->n = n;
    s_->rhs = std::move(rhs);
    s_->dyOut.resize(n);
    if (SUNContext_Create(nullptr, &s_->ctx) != 0) throw std::runtime_error("SUNDIALS: no context");
    s_->y = N_VNew_Serial(n, s_->ctx);
    s_->atol = N_VNew_Serial(n, s_->ctx);
    Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(s_->atol), n) = atol;
    N_VConst(0.0, s_->y);
    s_->mem = CVodeCreate(CV_BDF, s_->ctx);
    if (!s_->mem) throw std::runtime_error("CVODE: CVodeCreate failed");
    check(CVodeInit(s_->mem, &State::f, 0.0, s_->y), "CVodeInit");
    check(CVodeSVtolerances(s_->mem, rtol, s_->atol), "CVodeSVtolerances");
    check(CVodeSetUserData(s_->mem, s_.get()), "CVodeSetUserData");
    check(CVodeSetMaxNumSteps(s_->mem, 100000), "CVodeSetMaxNumSteps");
    check(CVodeSetErrFile(s_->mem, nullptr), "CVodeSetErrFile");  // failures are thrown, with CVODE's flag
    s_->A = SUNDenseMatrix(n, n, s_->ctx);
    s_->ls = SUNLinSol_Dense(s_->y, s_->A, s_->ctx);
    check(CVodeSetLinearSolver(s_->mem, s_->ls, s_->A), "CVodeSetLinearSolver");
}

void CvodeIntegrator::setJacobian(Jacobian jacobian) {
    s_->jacobian = std::move(jacobian);
    s_->jacOut.resize(s_->n, s_->n);
    check(CVodeSetJacFn(s_->mem, s_->jacobian ? &State::jac : nullptr), "CVodeSetJacFn");
}

CvodeIntegrator::~CvodeIntegrator() {
    if (!s_) return;
    CVodeFree(&s_->mem);
    SUNLinSolFree(s_->ls);
    SUNMatDestroy(s_->A);
    N_VDestroy(s_->y);
    N_VDestroy(s_->atol);
    SUNContext_Free(&s_->ctx);
}

void CvodeIntegrator::advance(double t, double tOut, Eigen::VectorXd& y, bool restart) {
    if (y.size() != s_->n) throw std::invalid_argument("CVODE integrator: state of the wrong size");
    if (restart || !s_->started) {
        s_->steps += s_->stepsSinceRestart;
        s_->rhsEvals += s_->rhsSinceRestart;
        s_->jacs += s_->jacsSinceRestart;
        s_->stepsSinceRestart = s_->rhsSinceRestart = s_->jacsSinceRestart = 0;
        Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(s_->y), s_->n) = y;
        check(CVodeReInit(s_->mem, t, s_->y), "CVodeReInit");
        s_->started = true;
    }
    check(CVodeSetStopTime(s_->mem, tOut), "CVodeSetStopTime");
    sunrealtype reached = t;
    s_->error = nullptr;
    const int flag = CVode(s_->mem, tOut, s_->y, &reached, CV_NORMAL);
    if (s_->error) std::rethrow_exception(s_->error);
    if (flag < 0)
        throw std::runtime_error("CVODE failed at t = " + std::to_string(reached) + " s: " + CVodeGetReturnFlagName(flag));
    y = Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(s_->y), s_->n);
    long nst = 0, nfe = 0, nfeLs = 0;
    CVodeGetNumSteps(s_->mem, &nst);
    CVodeGetNumRhsEvals(s_->mem, &nfe);
    CVodeGetNumLinRhsEvals(s_->mem, &nfeLs);
    long nje = 0;
    CVodeGetNumJacEvals(s_->mem, &nje);
    s_->jacsSinceRestart = nje;
    s_->stepsSinceRestart = nst;
    s_->rhsSinceRestart = nfe + nfeLs;
}

long CvodeIntegrator::steps() const { return s_->steps + s_->stepsSinceRestart; }
long CvodeIntegrator::rhsEvaluations() const { return s_->rhsEvals + s_->rhsSinceRestart; }
long CvodeIntegrator::jacobianEvaluations() const { return s_->jacs + s_->jacsSinceRestart; }

}  // namespace mixload::rom
