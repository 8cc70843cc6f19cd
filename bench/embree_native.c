/* Native Embree 3 on relief's triangles: the strongest general ray tracer configuration that
 * bench/compare_embree.py sets beside relief (issue 37's "The anchors").
 *
 * It builds one scene over the triangles bench/native_anchor.py writes (relief's `triangles`
 * surface with the solid's walls and bottom, as compare_embree.py's solid_triangles makes
 * them) with RTC_BUILD_QUALITY_HIGH and no robust flag, then traces the premade ray files it
 * is told to, one run per command read from standard input:
 *
 *     primary RAYS OUT    rtcIntersect16 on packets of 16 consecutive rays (the files hold
 *                         them in relief's tile order, 16x16 tiles, Morton inside a tile, so
 *                         16 consecutive rays are a 4x4 block of pixels), coherent context;
 *     single RAYS OUT     rtcIntersect1, one ray a call (a reference line);
 *     shadow RAYS OUT     rtcOccluded16 on packets of 16 consecutive shadow rays.
 *
 * RAYS is raw float32, six a ray (origin x y z, direction x y z), every ray over [0, +inf).
 * The rays are read and the output buffers allocated and touched before the clock starts;
 * the timed part traces every ray on THREADS OpenMP threads (flush-to-zero and
 * denormals-are-zero set on each, as Embree asks), writing each hit's distance
 * (+inf for a miss) and unit geometric normal facing the ray (zeros for a miss), or each
 * shadow ray's occlusion (1 blocked, 0 free), into those buffers. When OUT is not "-", they
 * are written after the run to OUT.distance.f32 and OUT.normal.f32 (3 floats a ray) or
 * OUT.occluded.u8. Each command prints one JSON line: kind, rays, wall seconds, CPU seconds of
 * all threads, Mrays/s, hits (or blocked rays) and the peak resident set so far; the build
 * prints one line first.
 *
 * By hand (Debian: apt-get install -y libembree-dev):
 *
 *     gcc -O3 -march=native -fopenmp bench/embree_native.c -lembree3 -o embree_native
 *     printf 'primary rays.f32 -\nshadow shadow.f32 -\n' \
 *         | ./embree_native vertices.f32 triangles.u32 2
 */
#define _GNU_SOURCE
#include <embree3/rtcore.h>
#include <math.h>
#include <omp.h>
#include <pmmintrin.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Packets are 16 rays; each OpenMP thread takes this many packets (256 rays) at a time,
 * as relief's tracer takes batches of 256. */
#define PACKET 16
#define PACKETS_PER_TASK 16

static void fail(const char *what, const char *detail) {
    fprintf(stderr, "embree_native: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    exit(1);
}

static double clock_seconds(clockid_t clock) {
    struct timespec t;
    clock_gettime(clock, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static double now_seconds(void) { return clock_seconds(CLOCK_MONOTONIC); }

/* CPU seconds all threads of this process have run: on a loaded machine, rays per CPU
 * second times the thread count estimates the rate the threads would reach alone. */
static double cpu_seconds(void) { return clock_seconds(CLOCK_PROCESS_CPUTIME_ID); }

/* The peak resident set so far, in MiB, from /proc (getrusage's ru_maxrss would count the
 * pages of the Python process that forked this one); 0 where unknown. */
static double peak_rss_mib(void) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double kib = 0.0;
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "VmHWM: %lf kB", &kib) == 1) break;
    if (f) fclose(f);
    return kib / 1024.0;
}

/* The whole file at path, its size in bytes into *size. */
static void *read_file(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) fail("cannot open", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    void *data = malloc(n > 0 ? (size_t)n : 1);
    if (!data || fread(data, 1, (size_t)n, f) != (size_t)n) fail("cannot read", path);
    fclose(f);
    *size = (size_t)n;
    return data;
}

static void write_file(const char *prefix, const char *suffix, const void *data, size_t size) {
    char path[4200];
    snprintf(path, sizeof path, "%s%s", prefix, suffix);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, size, f) != size) fail("cannot write", path);
    fclose(f);
}

static void on_embree_error(void *user, enum RTCError code, const char *message) {
    (void)user;
    fprintf(stderr, "embree_native: Embree error %d: %s\n", (int)code, message);
    exit(1);
}

/* The scene over vertices (3 floats each) and triangles (3 indices each), committed. */
static RTCScene build_scene(RTCDevice device, const float *vertices, size_t vertex_count,
                            const uint32_t *triangles, size_t triangle_count) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry mesh = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(mesh, RTC_BUILD_QUALITY_HIGH);
    /* Embree's own buffers are padded for its 16-byte loads of the last vertex. */
    float *v = rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), vertex_count);
    uint32_t *t = rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                          3 * sizeof(uint32_t), triangle_count);
    memcpy(v, vertices, 3 * sizeof(float) * vertex_count);
    memcpy(t, triangles, 3 * sizeof(uint32_t) * triangle_count);
    rtcCommitGeometry(mesh);
    rtcAttachGeometry(scene, mesh);
    rtcReleaseGeometry(mesh);
    rtcCommitScene(scene);
    return scene;
}

/* What one thread traces with: packets 64-byte aligned (rtcIntersect16 requires it; stack
 * locals inside OpenMP-outlined bodies are not always aligned), allocated once. */
struct ThreadBuffers {
    struct RTCRayHit16 *hits;
    struct RTCRay16 *shadows;
    int *valid;
    struct RTCRayHit *single;
};

/* The outputs of one run, allocated and touched before it. */
struct Outputs {
    float *distance;    /* one a ray */
    float *normal;      /* three a ray */
    uint8_t *occluded;  /* one a shadow ray */
};

/* Fills lane k of the packet(s) from ray r (origin, direction) over [0, +inf). */
#define SET_LANE(P, k, r)                                                                     \
    do {                                                                                      \
        (P).org_x[k] = (r)[0]; (P).org_y[k] = (r)[1]; (P).org_z[k] = (r)[2];                 \
        (P).dir_x[k] = (r)[3]; (P).dir_y[k] = (r)[4]; (P).dir_z[k] = (r)[5];                 \
        (P).tnear[k] = 0.0f; (P).tfar[k] = INFINITY; (P).time[k] = 0.0f;                     \
        (P).mask[k] = 0xFFFFFFFFu; (P).id[k] = 0; (P).flags[k] = 0;                           \
    } while (0)

/* Distance and unit normal facing direction d of a hit (t, geom, Ng) into ray i's outputs. */
static inline void store_hit(struct Outputs *out, size_t i, const float *d, float t,
                             unsigned geom, float nx, float ny, float nz) {
    if (geom == RTC_INVALID_GEOMETRY_ID) {
        out->distance[i] = INFINITY;
        out->normal[3 * i] = out->normal[3 * i + 1] = out->normal[3 * i + 2] = 0.0f;
        return;
    }
    float scale = 1.0f / sqrtf(nx * nx + ny * ny + nz * nz);
    if (nx * d[3] + ny * d[4] + nz * d[5] > 0.0f) scale = -scale;
    out->distance[i] = t;
    out->normal[3 * i] = nx * scale;
    out->normal[3 * i + 1] = ny * scale;
    out->normal[3 * i + 2] = nz * scale;
}

/* Traces packet p (rays [16p, 16p + 16) of n) as kind says into out. */
static void trace_packet(RTCScene scene, struct ThreadBuffers *b, const char kind,
                         const float *rays, size_t n, size_t p, struct Outputs *out) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    size_t first = p * PACKET;
    size_t count = n - first < PACKET ? n - first : PACKET;
    for (size_t k = 0; k < PACKET; k++) {
        const float *r = rays + 6 * (first + (k < count ? k : 0));
        b->valid[k] = k < count ? -1 : 0;
        if (kind == 's') {
            SET_LANE(*b->shadows, k, r);
        } else {
            SET_LANE(b->hits->ray, k, r);
            b->hits->hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            b->hits->hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
    }
    if (kind == 's') {
        rtcOccluded16(b->valid, scene, &context, b->shadows);
        for (size_t k = 0; k < count; k++) out->occluded[first + k] = b->shadows->tfar[k] < 0.0f;
        return;
    }
    rtcIntersect16(b->valid, scene, &context, b->hits);
    const struct RTCHit16 *h = &b->hits->hit;
    for (size_t k = 0; k < count; k++) {
        store_hit(out, first + k, rays + 6 * (first + k), b->hits->ray.tfar[k], h->geomID[k],
                  h->Ng_x[k], h->Ng_y[k], h->Ng_z[k]);
    }
}

/* Traces ray i alone with rtcIntersect1 into out. */
static void trace_single(RTCScene scene, struct ThreadBuffers *b, const float *rays, size_t i,
                         struct Outputs *out) {
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    const float *r = rays + 6 * i;
    struct RTCRayHit *q = b->single;
    q->ray.org_x = r[0]; q->ray.org_y = r[1]; q->ray.org_z = r[2];
    q->ray.dir_x = r[3]; q->ray.dir_y = r[4]; q->ray.dir_z = r[5];
    q->ray.tnear = 0.0f; q->ray.tfar = INFINITY; q->ray.time = 0.0f;
    q->ray.mask = 0xFFFFFFFFu; q->ray.id = 0; q->ray.flags = 0;
    q->hit.geomID = RTC_INVALID_GEOMETRY_ID;
    q->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, q);
    store_hit(out, i, r, q->ray.tfar, q->hit.geomID, q->hit.Ng_x, q->hit.Ng_y, q->hit.Ng_z);
}

static void *aligned(size_t size) {
    void *p = aligned_alloc(64, (size + 63) / 64 * 64);
    if (!p) fail("out of memory", NULL);
    memset(p, 0, size);
    return p;
}

/* Runs one command: traces the rays of rays_path as kind says, prints its JSON line and
 * writes the outputs under out_prefix unless it is "-". */
static void run(RTCScene scene, struct ThreadBuffers *buffers, int threads, const char *kind,
                const char *rays_path, const char *out_prefix) {
    size_t bytes;
    float *rays = read_file(rays_path, &bytes);
    size_t n = bytes / (6 * sizeof(float));
    char k = kind[0] == 's' && kind[1] == 'h' ? 's' : kind[0] == 's' ? '1' : 'p';
    struct Outputs out = {0};
    if (k == 's') {
        out.occluded = aligned(n);
    } else {
        out.distance = aligned(n * sizeof(float));
        out.normal = aligned(3 * n * sizeof(float));
    }
    size_t packets = (n + PACKET - 1) / PACKET;
    double cpu_started = cpu_seconds();
    double started = now_seconds();
#pragma omp parallel num_threads(threads)
    {
        /* Flush to zero and denormals as zero on every tracing thread, as Embree asks. */
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
        struct ThreadBuffers *b = &buffers[omp_get_thread_num()];
        if (k == '1') {
#pragma omp for schedule(dynamic, PACKET * PACKETS_PER_TASK)
            for (size_t i = 0; i < n; i++) trace_single(scene, b, rays, i, &out);
        } else {
#pragma omp for schedule(dynamic, PACKETS_PER_TASK)
            for (size_t p = 0; p < packets; p++) trace_packet(scene, b, k, rays, n, p, &out);
        }
    }
    double seconds = now_seconds() - started;
    double cpu = cpu_seconds() - cpu_started;
    size_t found = 0;
    for (size_t i = 0; i < n; i++) found += k == 's' ? out.occluded[i] : isfinite(out.distance[i]);
    printf("{\"kind\": \"%s\", \"rays\": %zu, \"seconds\": %.6f, \"cpu_seconds\": %.6f, "
           "\"mrays_s\": %.3f, \"%s\": %zu, \"peak_mib\": %.1f}\n",
           kind, n, seconds, cpu, n / seconds / 1e6, k == 's' ? "blocked" : "hits", found,
           peak_rss_mib());
    fflush(stdout);
    if (strcmp(out_prefix, "-") != 0) {
        if (k == 's') {
            write_file(out_prefix, ".occluded.u8", out.occluded, n);
        } else {
            write_file(out_prefix, ".distance.f32", out.distance, n * sizeof(float));
            write_file(out_prefix, ".normal.f32", out.normal, 3 * n * sizeof(float));
        }
    }
    free(out.distance);
    free(out.normal);
    free(out.occluded);
    free(rays);
}

int main(int argc, char **argv) {
    if (argc != 4) fail("usage", "embree_native VERTICES.f32 TRIANGLES.u32 THREADS < commands");
    int threads = atoi(argv[3]);
    if (threads < 1) fail("THREADS must be at least 1", argv[3]);
    size_t vertex_bytes, triangle_bytes;
    float *vertices = read_file(argv[1], &vertex_bytes);
    uint32_t *triangles = read_file(argv[2], &triangle_bytes);

    double started = now_seconds();
    char config[64];
    snprintf(config, sizeof config, "threads=%d", threads);
    RTCDevice device = rtcNewDevice(config);
    if (!device) fail("rtcNewDevice failed", config);
    rtcSetDeviceErrorFunction(device, on_embree_error, NULL);
    RTCScene scene = build_scene(device, vertices, vertex_bytes / (3 * sizeof(float)), triangles,
                                 triangle_bytes / (3 * sizeof(uint32_t)));
    double build_seconds = now_seconds() - started;
    free(vertices);
    free(triangles);
    printf("{\"kind\": \"build\", \"triangles\": %zu, \"seconds\": %.3f, \"threads\": %d, "
           "\"embree\": \"%d.%d.%d\", \"peak_mib\": %.1f}\n",
           triangle_bytes / (3 * sizeof(uint32_t)), build_seconds, threads, RTC_VERSION_MAJOR,
           RTC_VERSION_MINOR, RTC_VERSION_PATCH, peak_rss_mib());
    fflush(stdout);

    struct ThreadBuffers *buffers = calloc((size_t)threads, sizeof *buffers);
    for (int t = 0; t < threads; t++) {
        buffers[t].hits = aligned(sizeof(struct RTCRayHit16));
        buffers[t].shadows = aligned(sizeof(struct RTCRay16));
        buffers[t].valid = aligned(PACKET * sizeof(int));
        buffers[t].single = aligned(sizeof(struct RTCRayHit));
    }
    char line[8192], kind[16], rays_path[4096], out_prefix[4096];
    while (fgets(line, sizeof line, stdin)) {
        if (sscanf(line, "%15s %4095s %4095s", kind, rays_path, out_prefix) != 3) continue;
        if (strcmp(kind, "primary") && strcmp(kind, "shadow") && strcmp(kind, "single"))
            fail("unknown command (primary, shadow or single)", kind);
        run(scene, buffers, threads, kind, rays_path, out_prefix);
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
    return 0;
}
