/* A fake Force Dimension DHD library for tests: the subset of libdhd that
 * paintapp.haptics.devices.forcedimension calls, over a simulated stylus held by a simulated
 * hand.
 *
 * DHD conventions kept: metres, newtons, newton-metres, the DHD frame (x toward the user, y to
 * the right, z up), calls return 0 (or DHD_TIMEGUARD, 1) on success and -1 on error with the
 * reason in dhdErrorGetLastStr(), a device opens with forces disabled and brakes on.
 *
 * The device's watchdog is modelled as the hardware has it: outside the application. The
 * "device" state lives in a file mapped shared (PAINTAPP_FAKE_DHD_STATE; private memory without
 * it), and the output the motors would give is computed by fakeDhdOutput() from the time of the
 * last call the application made: past the watchdog time it is zero and the trip is recorded.
 * A thread in the library applies the same rule while the application lives; after the
 * application is killed, any process mapping the same file sees the same rule applied.
 */
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

typedef struct {
    double last_call_s, watchdog_s, max_force_n;
    double force[3], torque[3];
    double max_force_seen, max_force_after_trip;
    long writes, nonfinite, over, trips, calls;
    int open, forces_on, brakes, expert, type, closed;
} Device;

static Device g_private;
static Device *g = &g_private;
static char g_err[128] = "no error";
static int g_errcode = 0;
static long g_fail_after = -1;
static int g_no_device = 0;
static double g_x[3], g_v[3];
static long g_steps = 0;
static pthread_t g_wd;
static double g_wd_scale = 1.0;
static volatile int g_wd_run = 0;

static double now_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void map_path(const char *path) {
    int fd = open(path, O_RDWR | O_CREAT, 0600);
    if (fd < 0) return;
    if (ftruncate(fd, sizeof(Device)) == 0) {
        void *p = mmap(NULL, sizeof(Device), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
        if (p != MAP_FAILED) g = (Device *)p;
    }
    close(fd);
}

static void map_state(void) {
    const char *path = getenv("PAINTAPP_FAKE_DHD_STATE");
    if (path && g == &g_private) map_path(path);
}

static int fail(int code, const char *text) {
    g_errcode = code;
    strncpy(g_err, text, sizeof g_err - 1);
    return -1;
}

/* The firmware's rule: output is the commanded force while forces are on, the brakes off and
 * the application called within the watchdog time; otherwise zero (and a trip is recorded). */
static void firmware(double *out) {
    int live = g->open && g->forces_on && !g->brakes;
    if (live && g->watchdog_s > 0 && now_s() - g->last_call_s > g->watchdog_s * g_wd_scale) {
        g->trips++;
        g->forces_on = 0; g->brakes = 1;
        memset(g->force, 0, sizeof g->force); memset(g->torque, 0, sizeof g->torque);
        live = 0;
    }
    for (int i = 0; i < 3; i++) {
        out[i] = live ? g->force[i] : 0.0;
        out[3 + i] = live ? g->torque[i] : 0.0;
    }
}

static void *watchdog_thread(void *arg) {
    (void)arg;
    double out[6];
    struct timespec d = {0, 500000};
    while (g_wd_run) { firmware(out); nanosleep(&d, NULL); }
    return NULL;
}

static int touch(void) {
    g->calls++;
    if (!g->open) return fail(2, "no device open");
    if (g_fail_after >= 0 && g->calls > g_fail_after) return fail(3, "communication error (device unplugged)");
    g->last_call_s = now_s();
    return 0;
}

static void target(double t, double *p, double *v) {
    double w = 2.0 * M_PI, r = 0.03;
    p[0] = r * cos(w * t); p[1] = r * sin(w * t);
    v[0] = -r * w * sin(w * t); v[1] = r * w * cos(w * t);
    if (t < 0.3) {
        double ph = M_PI * t / 0.3;
        p[2] = -0.002 + 0.012 * 0.5 * (1.0 + cos(ph));
        v[2] = -0.012 * 0.5 * sin(ph) * M_PI / 0.3;
    } else { p[2] = -0.002; v[2] = 0.0; }
}

static void step_hand(void) {
    double p[3], v[3], out[6], h = 1e-3, k = 300.0, c = 3.0, m = 0.25;
    target(g_steps * 1e-3, p, v);
    firmware(out);
    for (int i = 0; i < 3; i++) {
        g_v[i] += h * (k * (p[i] - g_x[i]) + c * (v[i] - g_v[i]) + out[i]) / m;
        g_x[i] += h * g_v[i];
    }
    g_steps++;
}

int dhdOpen(void) {
    map_state();
    if (g_no_device || getenv("PAINTAPP_FAKE_DHD_NO_DEVICE")) return fail(1, "no device found");
    if (g->open) return fail(4, "device already open");
    double p[3], v[3];
    int type = g->type ? g->type : 63;
    memset(g, 0, sizeof *g);
    g->type = type; g->open = 1; g->brakes = 1; g->max_force_n = -1.0; g->last_call_s = now_s();
    target(0.0, p, v);
    for (int i = 0; i < 3; i++) { g_x[i] = p[i]; g_v[i] = 0.0; }
    g_steps = 0;
    return 0;
}

int dhdClose(signed char id) {
    (void)id;
    if (!g->open) return fail(2, "no device open");
    g_wd_run = 0;
    if (g_wd) { pthread_join(g_wd, NULL); g_wd = 0; }
    memset(g->force, 0, sizeof g->force); memset(g->torque, 0, sizeof g->torque);
    g->forces_on = 0; g->brakes = 1; g->open = 0; g->closed = 1;
    return 0;
}

int dhdStop(signed char id) {
    (void)id;
    if (touch() < 0) return -1;
    memset(g->force, 0, sizeof g->force); memset(g->torque, 0, sizeof g->torque);
    g->forces_on = 0; g->brakes = 1;
    return 0;
}

int dhdGetSystemType(signed char id) { (void)id; return touch() < 0 ? -1 : g->type; }
const char *dhdGetSystemName(signed char id) { (void)id; return g->type == 60 ? "Falcon (fake)" : g->type == 63 ? "delta.3 (fake)" : "omega.7 (fake)"; }
int dhdHasActiveWrist(signed char id) { (void)id; return g->type == 35 || g->type == 37; }
int dhdHasWrist(signed char id) { (void)id; return g->type != 60 && g->type != 63 && g->type != 33; }
int dhdHasGripper(signed char id) { (void)id; return g->type == 35 || g->type == 37; }

int dhdGetPosition(double *px, double *py, double *pz, signed char id) {
    (void)id;
    if (touch() < 0) return -1;
    step_hand();
    *px = g_x[0]; *py = g_x[1]; *pz = g_x[2];
    return 0;
}

int dhdGetOrientationFrame(double m[3][3], signed char id) {
    (void)id;
    if (touch() < 0) return -1;
    double c = cos(0.2), s = sin(0.2);
    double r[3][3] = {{c, 0, s}, {0, 1, 0}, {-s, 0, c}};
    memcpy(m, r, sizeof r);
    return 0;
}

unsigned int dhdGetButtonMask(signed char id) { (void)id; touch(); return (unsigned int)((g_steps / 500) % 2); }
int dhdGetGripperAngleRad(double *a, signed char id) { (void)id; if (touch() < 0) return -1; *a = 0.1; return 0; }

int dhdSetForceAndTorque(double fx, double fy, double fz, double tx, double ty, double tz, signed char id) {
    (void)id;
    if (touch() < 0) return -1;
    g->writes++;
    double f[6] = {fx, fy, fz, tx, ty, tz};
    for (int i = 0; i < 6; i++) if (!isfinite(f[i])) { g->nonfinite++; return fail(5, "invalid argument (non-finite)"); }
    double n = sqrt(fx * fx + fy * fy + fz * fz), s = 1.0;
    if (g->max_force_n > 0 && n > g->max_force_n * (1 + 1e-9)) { g->over++; s = g->max_force_n / n; }
    for (int i = 0; i < 3; i++) { g->force[i] = s * f[i]; g->torque[i] = f[3 + i]; }
    if (g->forces_on && !g->brakes && n * s > g->max_force_seen) g->max_force_seen = n * s;
    return 0;
}

int dhdEnableForce(unsigned char on, signed char id) {
    (void)id;
    if (touch() < 0) return -1;
    g->forces_on = on ? 1 : 0;
    if (!on) { memset(g->force, 0, sizeof g->force); memset(g->torque, 0, sizeof g->torque); }
    return 0;
}

int dhdSetBrakes(int on, signed char id) { (void)id; if (touch() < 0) return -1; g->brakes = on ? 1 : 0; return 0; }

int dhdSetWatchdog(unsigned char val, signed char id) {
    (void)id;
    if (touch() < 0) return -1;
    g->watchdog_s = 125e-6 * (double)val;
    if (val && !g_wd_run) { g_wd_run = 1; pthread_create(&g_wd, NULL, watchdog_thread, NULL); }
    return 0;
}

int dhdGetWatchdog(unsigned char *val, signed char id) { (void)id; if (touch() < 0) return -1; *val = (unsigned char)lround(g->watchdog_s / 125e-6); return 0; }
int dhdSetMaxForce(double f, signed char id) { (void)id; if (touch() < 0) return -1; g->max_force_n = f; return 0; }
double dhdGetMaxForce(signed char id) { (void)id; return g->max_force_n; }
int dhdEnableExpertMode(void) { g->expert = 1; return 0; }
int dhdDisableExpertMode(void) { g->expert = 0; return 0; }
int dhdErrorGetLast(void) { return g_errcode; }
const char *dhdErrorGetLastStr(void) { return g_err; }

/* test-only */
void fakeDhdSetType(int type) { g->type = type; }
/* stretch the watchdog (tests on a virtual clock run at no fixed pace: a stall of the shared
 * machine must not trip it there) */
void fakeDhdWatchdogScale(double scale) { g_wd_scale = scale; }
void fakeDhdSetNoDevice(int on) { g_no_device = on; }
void fakeDhdFailAfter(long calls) { g_fail_after = calls; }
/* look at (and act as) the device whose state lives in ``path`` */
void fakeDhdMapPath(const char *path) {
    if (g != &g_private) munmap(g, sizeof(Device));
    g = &g_private;
    map_path(path);
}
/* forces and torques the motors give now (applies the watchdog rule) */
void fakeDhdOutput(double *out) { firmware(out); }
/* writes, nonfinite, over-limit, watchdog trips, watchdog s, max force seen, open, forces on,
 * brakes, closed, commanded force x y z, seconds since the last call, max force limit */
void fakeDhdRecord(double *out) {
    out[0] = (double)g->writes; out[1] = (double)g->nonfinite; out[2] = (double)g->over;
    out[3] = (double)g->trips; out[4] = g->watchdog_s; out[5] = g->max_force_seen;
    out[6] = g->open; out[7] = g->forces_on; out[8] = g->brakes; out[9] = g->closed;
    out[10] = g->force[0]; out[11] = g->force[1]; out[12] = g->force[2];
    out[13] = now_s() - g->last_call_s; out[14] = g->max_force_n;
}
void fakeDhdReset(void) {
    g_wd_run = 0;
    if (g_wd) { pthread_join(g_wd, NULL); g_wd = 0; }
    memset(g, 0, sizeof *g);
    g_fail_after = -1; g_no_device = 0; g_errcode = 0; g_wd_scale = 1.0; strcpy(g_err, "no error");
}
