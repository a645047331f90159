/*
 * Battery cost of the app's capture thread (issue 23): a phone's streams (accelerometer and
 * gyroscope at 200 Hz, magnetometer at 100 Hz, each event offered at its own time, as the sensor
 * thread does without hardware batching) through the app's real capture path for a while of
 * real time, in two cases: recording with nothing on screen (the recorder writing a session on
 * disk) and the live screen visible without recording. Counts the capture thread's wake-ups (its
 * voluntary context switches, from /proc/self/task/TID/status: each is one sleep ended) per
 * second and its CPU time (ThreadMXBean) per minute. The sensor thread's own wake-ups (one per
 * event delivered by Android) are not the capture's and are not counted.
 * A third case records with hardware batching: the sensors registered with a report latency
 * (2 s, what half of a shared FIFO of 2000 events holds at these rates), and the benchmark, as
 * the sensor thread, delivers as the FIFO would: every 2 s each sensor's gathered events at once,
 * one sensor after another.
 * Run: java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.CaptureWakeUps [seconds]
 * (Linux only: /proc.)
 */
package dev.motionfusion.bench;

import dev.motionfusion.app.fusion.Capture;
import dev.motionfusion.app.record.CoreSessionFormat;
import dev.motionfusion.app.record.Recorder;
import dev.motionfusion.app.sensor.EventRing;
import dev.motionfusion.core.event.SessionStream;
import dev.motionfusion.core.session.SessionMetadata;
import java.lang.management.ManagementFactory;
import java.lang.management.ThreadMXBean;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.Comparator;
import java.util.concurrent.locks.LockSupport;
import java.util.stream.Stream;
import kotlin.Unit;

public final class CaptureWakeUps {
    private CaptureWakeUps() {}

    public static void main(String[] args) throws Exception {
        double seconds = args.length > 0 ? Double.parseDouble(args[0]) : 30.0;
        run("recording, nothing on screen", seconds, false, 0);
        if (batching()) run("recording, nothing on screen, hardware batching (2 s)", seconds, false, BATCH_LATENCY_US);
        run("live screen visible, not recording", seconds, true, 0);
    }

    /** The report latency of the batching case: half of a shared FIFO of 2000 events at 500 events/s. */
    static final int BATCH_LATENCY_US = 2_000_000;

    /** True when the capture on the class path can batch (not before issue 23's batching). */
    private static boolean batching() {
        try {
            FloodCapture.class.getDeclaredMethod("threaded", EventRing.class, int.class);
            Class.forName("dev.motionfusion.app.sensor.ReportLatency");
            return true;
        } catch (ReflectiveOperationException e) {
            return false;
        }
    }

    private static void run(String what, double seconds, boolean onScreen, int latencyUs) throws Exception {
        Path dir = Files.createTempDirectory("capture-wakeups");
        EventRing ring = new EventRing(Capture.DEFAULT_RING_CAPACITY);
        Capture capture = latencyUs > 0 ? FloodCapture.threaded(ring, latencyUs) : FloodCapture.threaded(ring); // acquired once, with its thread
        if (onScreen) user(capture, "acquire"); // and by a screen showing it
        Recorder recorder = null;
        if (!onScreen) {
            recorder = new Recorder(CoreSessionFormat.INSTANCE.create(dir.resolve("s").toFile(), new SessionMetadata()),
                r -> Unit.INSTANCE, 500_000_000L, () -> Long.MAX_VALUE, 0L, 2_000_000_000L, 100_000_000L, null, 60_000_000_000L, null, Long.MIN_VALUE);
            FloodCapture.attach(capture, recorder);
        }
        Thread thread = named("capture");
        Path task = task("capture");
        ThreadMXBean mx = ManagementFactory.getThreadMXBean();
        SessionStream[] streams = {SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE, SessionStream.MAGNETOMETER};
        long[] periodNs = {5_000_000L, 5_000_000L, 10_000_000L};
        long[] next = new long[3];
        float[] v = {0.1f, 0.2f, 9.8f};
        long start = System.nanoTime();
        for (int i = 0; i < 3; i++) next[i] = start;
        long switches0 = switches(task);
        long cpu0 = mx.getThreadCpuTime(thread.getId());
        long end = start + (long) (seconds * 1e9);
        long events = 0;
        long deliveries = 0;
        if (latencyUs == 0) {
            // Without batching: each event at its own time.
            while (true) {
                int k = 0;
                for (int i = 1; i < 3; i++) if (next[i] < next[k]) k = i;
                if (next[k] >= end) break;
                long wait = next[k] - System.nanoTime();
                if (wait > 0) LockSupport.parkNanos(wait);
                ring.offer(streams[k], next[k], 3, v, 3);
                next[k] += periodNs[k];
                events++;
                deliveries++;
            }
        } else {
            // As a FIFO: every latency, each sensor's events since the last delivery, one sensor after another.
            long latencyNs = latencyUs * 1000L;
            for (long at = start + latencyNs; at <= end; at += latencyNs) {
                long wait = at - System.nanoTime();
                if (wait > 0) LockSupport.parkNanos(wait);
                for (int k = 0; k < 3; k++) {
                    while (next[k] <= at) {
                        ring.offer(streams[k], next[k], 3, v, 3);
                        next[k] += periodNs[k];
                        events++;
                    }
                }
                deliveries++;
            }
        }
        long elapsed = System.nanoTime() - start;
        long switches = switches(task) - switches0;
        long cpu = mx.getThreadCpuTime(thread.getId()) - cpu0;
        if (recorder != null) FloodCapture.detach(capture, recorder);
        if (onScreen) user(capture, "release");
        capture.release();
        System.out.printf("%s: %,d events in %.1f s, delivered %.1f times a second; capture thread: %.1f wake-ups/s, %.0f ms CPU per minute; late %d%n",
            what, events, elapsed / 1e9, deliveries / (elapsed / 1e9), switches / (elapsed / 1e9), cpu / 1e6 / (elapsed / 6e10), lateEvents(capture));
        try (Stream<Path> files = Files.walk(dir)) {
            files.sorted(Comparator.reverseOrder()).forEach(p -> p.toFile().delete());
        }
    }

    /** Events the capture's reorder window passed on out of order (-1 where it does not count them). */
    private static long lateEvents(Capture c) {
        try {
            return c.getLateEvents();
        } catch (NoSuchMethodError e) {
            return -1;
        }
    }

    /** acquire(true) or release(true), a user on screen, where the capture has them (not before issue 23), else acquire() or release(). */
    private static void user(Capture c, String method) throws Exception {
        try {
            Capture.class.getMethod(method, boolean.class).invoke(c, true);
        } catch (NoSuchMethodException e) {
            Capture.class.getMethod(method).invoke(c);
        }
    }

    private static Thread named(String name) {
        for (Thread t : Thread.getAllStackTraces().keySet()) if (t.getName().equals(name)) return t;
        throw new IllegalStateException("no thread " + name);
    }

    /** The /proc task folder of the thread the JVM named [name]. */
    private static Path task(String name) throws Exception {
        try (Stream<Path> tasks = Files.list(Path.of("/proc/self/task"))) {
            for (Path p : (Iterable<Path>) tasks::iterator) {
                if (Files.readString(p.resolve("comm")).trim().equals(name)) return p;
            }
        }
        throw new IllegalStateException("no task " + name);
    }

    private static long switches(Path task) throws Exception {
        for (String line : Files.readAllLines(task.resolve("status"))) {
            if (line.startsWith("voluntary_ctxt_switches:")) return Long.parseLong(line.substring(line.indexOf(':') + 1).trim());
        }
        throw new IllegalStateException("no context switches in " + task);
    }
}
