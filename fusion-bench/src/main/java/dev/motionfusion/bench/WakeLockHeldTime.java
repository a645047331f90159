/*
 * Wake-lock held time per hour of recording (issue 41) on simulated phones with and without hardware
 * FIFOs and wake-up sensor variants, for an ordinary recording (every stream at the default 100 Hz) and
 * the still recording (accelerometers, gyroscopes and magnetometers, as fast as the phone delivers).
 *
 * Each phone is a set of sensors as android.hardware.Sensor describes them (wake-up flag, FIFO reserved
 * and maximum events, fastest period). The case comes from the app's own decision: the sensor hub's
 * choice of each stream's wake-up variant where it has a FIFO, ReportLatency.choose for the report
 * latency and WakeLockNeed.use for the lock (what meta.json's wake_lock records). Held: the lock is
 * held the whole hour. Let go: held only from Record until the recording runs; that part is measured
 * here through the app's real path (the session created, the recorder attached to the capture), and the
 * phone is woken once per report latency to take the batches.
 * The capture's CPU per hour is measured as CaptureWakeUps does: the streams are offered in real time
 * through the real capture and recorder (each event at its own time without a report latency, else a
 * FIFO's batch every latency), the capture thread's CPU time (ThreadMXBean) scaled to an hour; without
 * the lock that CPU time is the phone kept awake for the batches (with the system's own resume cost,
 * which a JVM cannot see, on top).
 * Run: java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.WakeLockHeldTime [seconds per case]
 */
package dev.motionfusion.bench;

import dev.motionfusion.app.fusion.Capture;
import dev.motionfusion.app.record.CoreSessionFormat;
import dev.motionfusion.app.record.Recorder;
import dev.motionfusion.app.sensor.EventRing;
import dev.motionfusion.app.sensor.ReportLatency;
import dev.motionfusion.app.sensor.SamplingRate;
import dev.motionfusion.app.sensor.SensorFifo;
import dev.motionfusion.app.sensor.WakeLockNeed;
import dev.motionfusion.core.event.SessionStream;
import dev.motionfusion.core.session.SessionMetadata;
import dev.motionfusion.core.session.WakeLockUse;
import java.lang.management.ManagementFactory;
import java.lang.management.ThreadMXBean;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.Comparator;
import java.util.EnumSet;
import java.util.HashMap;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Locale;
import java.util.Map;
import java.util.Set;
import java.util.concurrent.locks.LockSupport;
import java.util.stream.Collectors;
import java.util.stream.Stream;
import kotlin.Unit;

public final class WakeLockHeldTime {
    private WakeLockHeldTime() {}

    /** One sensor of a simulated phone: a wake-up one or not, its FIFO (reserved and maximum events), its fastest period. */
    record Sensor(boolean wakeUp, int fifoReserved, int fifoMax, int minDelayUs) {}

    /** A simulated phone: each stream's default sensor and, where it has one, its wake-up variant. */
    record Phone(String name, Map<SessionStream, Sensor> defaults, Map<SessionStream, Sensor> wakeUp) {
        /** What the sensor hub registers: the wake-up variant where it batches (a FIFO), else the default. */
        Map<SessionStream, Sensor> registering(Set<SessionStream> streams) {
            Map<SessionStream, Sensor> out = new LinkedHashMap<>();
            for (var e : defaults.entrySet()) {
                if (!streams.contains(e.getKey())) continue;
                Sensor w = wakeUp.get(e.getKey());
                out.put(e.getKey(), w != null && w.fifoMax() > 0 ? w : e.getValue());
            }
            return out;
        }
    }

    /** Every sensor stream of the app (SensorStreams.all). */
    private static final Set<SessionStream> ALL = EnumSet.of(
        SessionStream.ACCELEROMETER, SessionStream.ACCELEROMETER_UNCALIBRATED, SessionStream.GYROSCOPE, SessionStream.GYROSCOPE_UNCALIBRATED,
        SessionStream.MAGNETOMETER, SessionStream.MAGNETOMETER_UNCALIBRATED, SessionStream.ROTATION_VECTOR, SessionStream.GAME_ROTATION_VECTOR);

    /** The still recording's streams (RecordingService.STILL_STREAMS; that class needs the Android framework to load). */
    private static final Set<SessionStream> STILL = EnumSet.of(
        SessionStream.ACCELEROMETER, SessionStream.ACCELEROMETER_UNCALIBRATED, SessionStream.GYROSCOPE, SessionStream.GYROSCOPE_UNCALIBRATED,
        SessionStream.MAGNETOMETER, SessionStream.MAGNETOMETER_UNCALIBRATED);

    private static final Set<SessionStream> MAGNETIC = EnumSet.of(SessionStream.MAGNETOMETER, SessionStream.MAGNETOMETER_UNCALIBRATED);
    private static final Set<SessionStream> FUSED = EnumSet.of(SessionStream.ROTATION_VECTOR, SessionStream.GAME_ROTATION_VECTOR);

    /** Fastest periods: IMU 400 Hz, magnetometers 100 Hz, rotation vectors 200 Hz. */
    private static int minDelayUs(SessionStream s) {
        return MAGNETIC.contains(s) ? 10_000 : FUSED.contains(s) ? 5_000 : 2_500;
    }

    /** Every stream with a sensor of a FIFO of [fifoMax] events (a tenth reserved); [wakeUpOf]: the streams that also have a wake-up variant, its FIFO [wakeUpFifoMax]. */
    private static Phone phone(String name, int fifoMax, Set<SessionStream> wakeUpOf, int wakeUpFifoMax) {
        Map<SessionStream, Sensor> defaults = new LinkedHashMap<>();
        Map<SessionStream, Sensor> wakeUp = new LinkedHashMap<>();
        for (SessionStream s : ALL) {
            defaults.put(s, new Sensor(false, fifoMax / 10, fifoMax, minDelayUs(s)));
            if (wakeUpOf.contains(s)) wakeUp.put(s, new Sensor(true, wakeUpFifoMax / 10, wakeUpFifoMax, minDelayUs(s)));
        }
        return new Phone(name, defaults, wakeUp);
    }

    static List<Phone> phones() {
        Set<SessionStream> none = EnumSet.noneOf(SessionStream.class);
        Set<SessionStream> calibratedImu = EnumSet.of(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE, SessionStream.MAGNETOMETER);
        return List.of(
            phone("no FIFO, no wake-up sensors", 0, none, 0),
            phone("FIFO 3000, no wake-up sensors", 3000, none, 0),
            phone("FIFO 3000, wake-up acc/gyro/mag only", 3000, calibratedImu, 3000),
            phone("FIFO 3000, wake-up variant of every sensor", 3000, ALL, 3000),
            phone("wake-up variants, FIFO 20 events", 20, ALL, 20));
    }

    /** A recording: its streams and rate. */
    record Recording(String name, Set<SessionStream> streams, SamplingRate rate) {}

    static final Recording ORDINARY = new Recording("all 8 streams, 100 Hz", ALL, new SamplingRate.Hz(100));
    static final Recording STILL_RECORDING = new Recording("still: 6 streams, fastest", STILL, SamplingRate.Delay.FASTEST);

    /** The app's decision for [phone] recording [r]: report latency and the wake-lock case. */
    record Decision(int latencyUs, WakeLockUse use, Map<SessionStream, Double> eventsPerSecond) {}

    static Decision decide(Phone phone, Recording r) {
        Map<SessionStream, Sensor> reg = phone.registering(r.streams());
        List<SensorFifo> fifos = new ArrayList<>();
        Map<SessionStream, kotlin.Pair<Boolean, Integer>> flags = new LinkedHashMap<>();
        Map<SessionStream, Double> eps = new LinkedHashMap<>();
        for (var e : reg.entrySet()) {
            Sensor s = e.getValue();
            double perSecond = ReportLatency.INSTANCE.eventsPerSecond(r.rate(), s.minDelayUs());
            fifos.add(new SensorFifo(s.fifoReserved(), s.fifoMax(), perSecond));
            flags.put(e.getKey(), new kotlin.Pair<>(s.wakeUp(), s.fifoMax()));
            eps.put(e.getKey(), perSecond);
        }
        int latency = ReportLatency.INSTANCE.choose(fifos);
        return new Decision(latency, WakeLockNeed.Companion.use(flags, latency), eps);
    }

    public static void main(String[] args) throws Exception {
        double seconds = args.length > 0 ? Double.parseDouble(args[0]) : 10.0;
        Map<String, double[]> measured = new HashMap<>(); // by streams, rate and latency: {CPU s per hour, start ms}
        System.out.printf(Locale.ROOT, "| phone | recording | case (forced by) | report latency | wake lock held per hour | phone woken per hour | capture CPU per hour |%n|---|---|---|---|---|---|---|%n");
        for (Phone phone : phones()) {
            for (Recording r : List.of(ORDINARY, STILL_RECORDING)) {
                Decision d = decide(phone, r);
                String key = r.name() + "/" + d.latencyUs();
                double[] m = measured.get(key);
                if (m == null) {
                    m = run(d, seconds);
                    measured.put(key, m);
                }
                WakeLockUse use = d.use();
                int forcedBy = use.getForcedBy().size();
                String forced = forcedBy == 0 ? "" : forcedBy == r.streams().size() ? " (every stream)"
                    : " (" + use.getForcedBy().stream().map(SessionStream::getKey).collect(Collectors.joining(", ")) + ")";
                String held = use.getHeld() ? "3600 s" : String.format(Locale.ROOT, "%.0f ms (Record until running)", m[1]);
                String woken = use.getHeld() ? "kept awake" : String.format(Locale.ROOT, "%,.0f", 3600e6 / d.latencyUs());
                System.out.printf(Locale.ROOT, "| %s | %s | %s%s | %s | %s | %s | %.1f s |%n", phone.name(), r.name(), use.getReason(), forced,
                    d.latencyUs() == 0 ? "0" : String.format(Locale.ROOT, "%.2f s", d.latencyUs() / 1e6), held, woken, m[0]);
            }
        }
    }

    /**
     * Records [seconds] of the decision's streams through the real capture and recorder in real time;
     * returns the capture thread's CPU time scaled to an hour (s) and the time from "Record" (creating the
     * session) until the recorder is attached (ms), the part the lock covers when it is let go.
     */
    private static double[] run(Decision d, double seconds) throws Exception {
        Path dir = Files.createTempDirectory("wake-lock-held");
        EventRing ring = new EventRing(Capture.DEFAULT_RING_CAPACITY);
        Capture capture = d.latencyUs() > 0 ? FloodCapture.threaded(ring, d.latencyUs()) : FloodCapture.threaded(ring);
        long t0 = System.nanoTime();
        Recorder recorder = new Recorder(CoreSessionFormat.INSTANCE.create(dir.resolve("s").toFile(), new SessionMetadata()),
            r -> Unit.INSTANCE, 500_000_000L, () -> Long.MAX_VALUE, 0L, 2_000_000_000L, 100_000_000L, null, 60_000_000_000L, null, Long.MIN_VALUE);
        FloodCapture.attach(capture, recorder);
        double startMs = (System.nanoTime() - t0) / 1e6;
        Thread thread = null;
        for (Thread t : Thread.getAllStackTraces().keySet()) if (t.getName().equals("capture")) thread = t;
        if (thread == null) throw new IllegalStateException("no capture thread");
        ThreadMXBean mx = ManagementFactory.getThreadMXBean();
        List<SessionStream> streams = new ArrayList<>(d.eventsPerSecond().keySet());
        int n = streams.size();
        long[] periodNs = new long[n];
        for (int i = 0; i < n; i++) periodNs[i] = Math.round(1e9 / d.eventsPerSecond().get(streams.get(i)));
        float[] v = {0.1f, 0.2f, 9.8f, 0.01f, 0.02f, 0.03f};
        long start = System.nanoTime();
        long[] next = new long[n];
        java.util.Arrays.fill(next, start);
        long cpu0 = mx.getThreadCpuTime(thread.getId());
        long end = start + (long) (seconds * 1e9);
        if (d.latencyUs() == 0) {
            while (true) { // each event at its own time
                int k = 0;
                for (int i = 1; i < n; i++) if (next[i] < next[k]) k = i;
                if (next[k] >= end) break;
                long wait = next[k] - System.nanoTime();
                if (wait > 0) LockSupport.parkNanos(wait);
                ring.offer(streams.get(k), next[k], 3, v, streams.get(k).getValueColumns().size());
                next[k] += periodNs[k];
            }
        } else {
            long latencyNs = d.latencyUs() * 1000L; // a FIFO's batch every latency, one sensor after another
            for (long at = start + latencyNs; at <= end; at += latencyNs) {
                long wait = at - System.nanoTime();
                if (wait > 0) LockSupport.parkNanos(wait);
                for (int k = 0; k < n; k++) {
                    while (next[k] <= at) {
                        ring.offer(streams.get(k), next[k], 3, v, streams.get(k).getValueColumns().size());
                        next[k] += periodNs[k];
                    }
                }
            }
        }
        long elapsed = System.nanoTime() - start;
        long cpu = mx.getThreadCpuTime(thread.getId()) - cpu0;
        FloodCapture.detach(capture, recorder);
        capture.release();
        try (Stream<Path> files = Files.walk(dir)) {
            files.sorted(Comparator.reverseOrder()).forEach(p -> p.toFile().delete());
        }
        return new double[] {cpu / 1e9 * (3600e9 / elapsed), startMs};
    }
}
