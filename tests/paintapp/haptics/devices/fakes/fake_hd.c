/* A fake OpenHaptics HD library for tests: the subset of libHD that
 * paintapp.haptics.devices.openhaptics calls, over a simulated stylus held by a simulated hand.
 *
 * HD conventions kept: millimetres, newtons, the HD frame (x right, y up, z toward the user),
 * calls that set state are legal only inside hdBeginFrame/hdEndFrame, errors are queued and
 * popped by hdGetError, forces reach the "motors" only while the scheduler runs and force output
 * is enabled, max-force clamping and ramping act when enabled.
 *
 * Test-only entry points (fakeHd*): a manual scheduler (the test runs the callbacks, on a
 * virtual clock), error injection, and a record of everything written.
 *
 * The device's own safety is modelled as the hardware has it: outside the application. A Touch
 * or Phantom drives its motors only while the host's servo loop keeps sending frames; when the
 * frames stop (the HD scheduler dies with its process) the amplifiers are disabled. The "device"
 * state (the output, the time the last frame ended, the device's timeout) lives in a file mapped
 * shared (PAINTAPP_FAKE_HD_STATE; private memory without it), and fakeHdOutput() gives what the
 * motors give now: the last frame's output while it is at most the timeout old, zero after. Any
 * process mapping the same file (fakeHdMapPath) sees the same rule applied, so it holds after
 * the application is killed.
 */
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

typedef unsigned int HHD;
typedef unsigned int HDenum;
typedef unsigned int HDerror;
typedef unsigned int HDCallbackCode;
typedef unsigned long HDSchedulerHandle;
typedef HDCallbackCode (*HDSchedulerCallback)(void *);
typedef struct { HDerror errorCode; int internalErrorCode; HHD hHD; } HDErrorInfo;

#define MAX_FORCE_N 3.3
#define CONT_FORCE_N 0.88
#define RAMP_FRAMES 50
#define MAX_TASKS 8
#define MAX_ERRORS 16
/* the amplifiers are disabled this long after the last servo frame (ten 1 kHz frames) */
#define DEVICE_TIMEOUT_S 0.010

/* what the device itself holds: the output of the last frame (HD frame, N), when that frame
 * ended (CLOCK_MONOTONIC, s), its timeout, frames run, timeouts seen, initialised, scheduler on */
typedef struct {
    double out[3];
    double last_frame_s, timeout_s;
    long frames, timeouts;
    int init, running, timed_out;
} Device;

static Device g_private;
static Device *g = &g_private;

static int g_in_frame = 0, g_manual = 0, g_output_dof = 3;
static unsigned int g_caps = 0;            /* bit i: capability 0x4000 + i or 0x2606/0x2607 */
static HDerror g_errors[MAX_ERRORS];
static int g_nerr = 0;
static HDSchedulerCallback g_tasks[MAX_TASKS];
static void *g_data[MAX_TASKS];
static pthread_t g_thread;
static volatile int g_stop = 0;
static long g_inject_at = -1;
static HDerror g_inject_code = 0;
static int g_no_device = 0;

/* the stylus: position m and velocity m/s in the HD frame */
static double g_x[3], g_v[3];
static double g_cmd[3], g_cmd_t[3];
static long g_writes = 0, g_nonfinite = 0, g_over = 0, g_ramp = 0;
static double g_max_out = 0.0;
static long g_frames_outside = 0;

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
    const char *path = getenv("PAINTAPP_FAKE_HD_STATE");
    if (path && g == &g_private) map_path(path);
}

/* The device's rule: the motors give the last frame's output while the device is initialised
 * and that frame ended at most the timeout ago; otherwise zero (and a timeout is recorded). */
static void device_output(double *out) {
    int live = g->init && g->last_frame_s > 0.0 && now_s() - g->last_frame_s <= g->timeout_s;
    if (!live && g->init && g->last_frame_s > 0.0 && !g->timed_out) { g->timed_out = 1; g->timeouts++; }
    for (int i = 0; i < 3; i++) out[i] = live ? g->out[i] : 0.0;
}

static void push_error(HDerror code) {
    if (g_nerr < MAX_ERRORS) g_errors[g_nerr++] = code;
}

static int cap_bit(HDenum cap) {
    if (cap >= 0x4000 && cap <= 0x4004) return (int)(cap - 0x4000);
    if (cap == 0x2606) return 8;
    if (cap == 0x2607) return 9;
    return -1;
}

static int enabled(HDenum cap) { int b = cap_bit(cap); return b >= 0 && (g_caps >> b) & 1u; }

/* the hand's target: going round a 30 mm circle once a second, and every 2 s coming down from
 * 10 mm above the canvas (y = 0) to 2 mm below over 0.3 s, staying 1.4 s, lifting over 0.3 s
 * (the scheduler runs before the application's loop starts: the next stroke engages it) */
static void target(double t, double *p, double *v) {
    double w = 2.0 * M_PI, r = 0.03, tm = fmod(t, 2.0);
    p[0] = r * cos(w * t); p[2] = -r * sin(w * t);
    v[0] = -r * w * sin(w * t); v[2] = -r * w * cos(w * t);
    if (tm < 0.3) {
        double ph = M_PI * tm / 0.3;
        p[1] = -0.002 + 0.012 * 0.5 * (1.0 + cos(ph));
        v[1] = -0.012 * 0.5 * sin(ph) * M_PI / 0.3;
    } else if (tm < 1.7) {
        p[1] = -0.002; v[1] = 0.0;
    } else {
        double ph = M_PI * (tm - 1.7) / 0.3;
        p[1] = -0.002 + 0.012 * 0.5 * (1.0 - cos(ph));
        v[1] = 0.012 * 0.5 * sin(ph) * M_PI / 0.3;
    }
}

static void reset_hand(void) {
    double p[3], v[3];
    target(0.0, p, v);
    for (int i = 0; i < 3; i++) { g_x[i] = p[i]; g_v[i] = 0.0; g_cmd[i] = g->out[i] = g_cmd_t[i] = 0.0; }
}

static void advance_hand(void) {
    double p[3], v[3], h = 1e-3, k = 300.0, c = 3.0, m = 0.25;
    target(g->frames * 1e-3, p, v);
    for (int i = 0; i < 3; i++) {
        g_v[i] += h * (k * (p[i] - g_x[i]) + c * (v[i] - g_v[i]) + g->out[i]) / m;
        g_x[i] += h * g_v[i];
    }
}

HHD hdInitDevice(const char *name) {
    (void)name;
    if (g_no_device || getenv("PAINTAPP_FAKE_HD_NO_DEVICE")) { push_error(0x0302); return 0xFFFFFFFFu; }
    map_state();
    if (g->init) { push_error(0x0301); return 0xFFFFFFFFu; }
    /* a fresh device; a scheduler this process already runs keeps running (a shared file left
     * by a dead process holds no scheduler of ours) */
    int running = g == &g_private ? g->running : 0;
    memset(g, 0, sizeof *g);
    g->init = 1; g->running = running; g->timeout_s = DEVICE_TIMEOUT_S; g_caps = 0; g_ramp = 0;
    reset_hand();
    return 1;
}

void hdDisableDevice(HHD h) {
    (void)h;
    for (int i = 0; i < 3; i++) g->out[i] = g_cmd[i] = 0.0;
    g->init = 0; g_caps = 0;
}

void hdMakeCurrentDevice(HHD h) { if (h != 1) push_error(0x0104); }

HDErrorInfo hdGetError(void) {
    HDErrorInfo e = {0, 0, 1};
    if (g_nerr > 0) { e.errorCode = g_errors[0]; memmove(g_errors, g_errors + 1, sizeof(HDerror) * (size_t)(--g_nerr)); }
    return e;
}

const char *hdGetErrorString(HDerror code) {
    switch (code) {
    case 0x0100: return "Invalid enumerant";
    case 0x0101: return "Invalid value";
    case 0x0102: return "Invalid operation";
    case 0x0104: return "Invalid device handle";
    case 0x0203: return "Maximum velocity exceeded";
    case 0x0301: return "Device already initiated";
    case 0x0302: return "Communication error";
    case 0x0400: return "Illegal begin frame";
    case 0x0401: return "Illegal end frame";
    default: return "HD error";
    }
}

void hdEnable(HDenum cap) { int b = cap_bit(cap); if (b < 0) push_error(0x0100); else g_caps |= 1u << b; if (cap == 0x4000) g_ramp = 0; }
void hdDisable(HDenum cap) { int b = cap_bit(cap); if (b < 0) push_error(0x0100); else g_caps &= ~(1u << b); }

void hdBeginFrame(HHD h) {
    if (h != 1 || !g->init) { push_error(0x0104); return; }
    if (g_in_frame) { push_error(0x0400); return; }
    if (!g->running) g_frames_outside++;
    g_in_frame = 1;
    advance_hand();
    g->frames++;
}

void hdEndFrame(HHD h) {
    if (h != 1 || !g_in_frame) { push_error(0x0401); return; }
    g_in_frame = 0;
    double gain = 1.0;
    if (enabled(0x4002)) { g_ramp++; gain = g_ramp >= RAMP_FRAMES ? 1.0 : (double)g_ramp / RAMP_FRAMES; }
    double n = 0.0;
    for (int i = 0; i < 3; i++) {
        g->out[i] = enabled(0x4000) ? gain * g_cmd[i] : 0.0;
        n += g->out[i] * g->out[i];
    }
    n = sqrt(n);
    if (n > g_max_out) g_max_out = n;
    g->last_frame_s = now_s(); g->timed_out = 0;
    if (g_inject_at >= 0 && g->frames >= g_inject_at) { push_error(g_inject_code); g_inject_at = -1; }
}

static void get_doubles(HDenum p, double *out) {
    switch (p) {
    case 0x2050: for (int i = 0; i < 3; i++) out[i] = g_x[i] * 1000.0; return;
    case 0x2052: {
        /* the stylus tilted 0.3 rad about the HD x axis, column-major */
        double c = cos(0.3), s = sin(0.3);
        double m[16] = {1, 0, 0, 0, 0, c, s, 0, 0, -s, c, 0, g_x[0] * 1e3, g_x[1] * 1e3, g_x[2] * 1e3, 1};
        memcpy(out, m, sizeof m);
        return;
    }
    case 0x2551: { double b[6] = {-80, -60, -35, 80, 60, 35}; memcpy(out, b, sizeof b); return; }
    case 0x2602: out[0] = 1.26; return;
    case 0x2603: out[0] = MAX_FORCE_N; return;
    case 0x2604: out[0] = CONT_FORCE_N; return;
    case 0x2609: out[0] = 0.005; return;
    case 0x2623: out[0] = 150.0; return;
    case 0x2700: for (int i = 0; i < 3; i++) out[i] = g->out[i]; return;
    default: push_error(0x0100);
    }
}

void hdGetDoublev(HDenum p, double *out) { if (!g->init) { push_error(0x0104); return; } get_doubles(p, out); }

void hdGetIntegerv(HDenum p, int *out) {
    if (!g->init) { push_error(0x0104); return; }
    switch (p) {
    case 0x2000: out[0] = (g->frames / 500) % 2; return;  /* button 1 toggles every 0.5 s */
    case 0x2553: out[0] = 6; return;
    case 0x2554: out[0] = g_output_dof; return;
    default: push_error(0x0100);
    }
}

const char *hdGetString(HDenum p) {
    if (p == 0x2501) return "Touch (fake)";
    push_error(0x0100);
    return NULL;
}

void hdSetDoublev(HDenum p, const double *v) {
    if (!g_in_frame) { push_error(0x0102); return; }
    if (p == 0x2700) {
        g_writes++;
        if (!(isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]))) {
            g_nonfinite++; push_error(0x0101);
            for (int i = 0; i < 3; i++) g_cmd[i] = 0.0;
            return;
        }
        double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]), s = 1.0;
        if (n > CONT_FORCE_N * (1 + 1e-9)) { g_over++; if (enabled(0x4001) && n > MAX_FORCE_N) s = MAX_FORCE_N / n; }
        for (int i = 0; i < 3; i++) g_cmd[i] = s * v[i];
    } else if (p == 0x2701) {
        if (g_output_dof < 6) { push_error(0x0100); return; }
        for (int i = 0; i < 3; i++) g_cmd_t[i] = v[i];
    } else push_error(0x0100);
}

/* the scheduler */
HDSchedulerHandle hdScheduleAsynchronous(HDSchedulerCallback cb, void *data, unsigned short prio) {
    (void)prio;
    for (int i = 0; i < MAX_TASKS; i++)
        if (!g_tasks[i]) { g_tasks[i] = cb; g_data[i] = data; return (HDSchedulerHandle)(i + 1); }
    push_error(0x0501);
    return 0;
}

void hdUnschedule(HDSchedulerHandle h) { if (h >= 1 && h <= MAX_TASKS) g_tasks[h - 1] = NULL; }

static void run_tasks(void) {
    for (int i = 0; i < MAX_TASKS; i++)
        if (g_tasks[i] && g_tasks[i](g_data[i]) == 0) g_tasks[i] = NULL;
}

static void *scheduler(void *arg) {
    (void)arg;
    struct timespec next;
    clock_gettime(CLOCK_MONOTONIC, &next);
    while (!g_stop) {
        run_tasks();
        next.tv_nsec += 1000000;
        if (next.tv_nsec >= 1000000000) { next.tv_nsec -= 1000000000; next.tv_sec++; }
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
    }
    return NULL;
}

void hdStartScheduler(void) {
    if (g->running) return;
    g->running = 1; g_stop = 0;
    if (!g_manual && !getenv("PAINTAPP_FAKE_HD_MANUAL")) pthread_create(&g_thread, NULL, scheduler, NULL);
    else g_manual = 1;
}

void hdStopScheduler(void) {
    if (!g->running) return;
    g_stop = 1;
    if (!g_manual) pthread_join(g_thread, NULL);
    g->running = 0;
}

/* test-only */
void fakeHdSetManual(int on) { g_manual = on; }
void fakeHdSetNoDevice(int on) { g_no_device = on; }
void fakeHdSetOutputDof(int dof) { g_output_dof = dof; }
void fakeHdInjectError(unsigned int code, long at_frame) { g_inject_code = code; g_inject_at = at_frame; }
int fakeHdRunScheduler(int ticks) {
    if (!g->running) return 0;
    for (int i = 0; i < ticks; i++) run_tasks();
    return ticks;
}
/* look at (and act as) the device whose state lives in ``path`` */
void fakeHdMapPath(const char *path) {
    if (g != &g_private) munmap(g, sizeof(Device));
    g = &g_private;
    map_path(path);
}
/* the force the motors give now (HD frame, N; the device's timeout applied), then the seconds
 * since the last frame ended */
void fakeHdOutput(double *out) {
    device_output(out);
    out[3] = now_s() - g->last_frame_s;
}
/* frames, writes, nonfinite, over-limit, max output N, output x y z (HD frame), caps, running,
 * initialised, frames run outside the scheduler, the device's timeout s, timeouts seen */
void fakeHdRecord(double *out) {
    out[0] = (double)g->frames; out[1] = (double)g_writes; out[2] = (double)g_nonfinite;
    out[3] = (double)g_over; out[4] = g_max_out;
    out[5] = g->out[0]; out[6] = g->out[1]; out[7] = g->out[2];
    out[8] = (double)g_caps; out[9] = (double)g->running; out[10] = (double)g->init;
    out[11] = (double)g_frames_outside; out[12] = g->timeout_s; out[13] = (double)g->timeouts;
}
void fakeHdReset(void) {
    memset(g, 0, sizeof *g);
    g_in_frame = 0; g_caps = 0; g_nerr = 0; g_inject_at = -1;
    g_writes = g_nonfinite = g_over = g_ramp = g_frames_outside = 0; g_max_out = 0.0;
    for (int i = 0; i < MAX_TASKS; i++) g_tasks[i] = NULL;
    g_no_device = 0; g_output_dof = 3;
    reset_hand();
}
