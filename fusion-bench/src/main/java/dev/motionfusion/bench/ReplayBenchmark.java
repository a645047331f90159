/*
 * JMH benchmark of `fusion replay` end to end on a 1-hour, 200 Hz, 3-sensor session (accelerometer,
 * gyroscope, magnetometer: 2,160,000 rows in three CSV files, about 90 MB): read and parse the
 * files, merge them by timestamp, run the filter (defaults), and optionally format the output CSV
 * (720,000 rows) into a discarding stream. One operation = one whole replay; rows/s = 2,160,000 / (s/op).
 * Run: java -jar fusion-bench/target/benchmarks.jar ReplayBenchmark  (see docs/BENCHMARKS.md).
 */
package dev.motionfusion.bench;

import dev.motionfusion.core.filter.FilterSettings;
import dev.motionfusion.core.input.Recording;
import dev.motionfusion.core.replay.ReplayCounts;
import dev.motionfusion.core.replay.ReplayCsvWriter;
import dev.motionfusion.core.replay.ReplayListener;
import dev.motionfusion.core.replay.ReplayStep;
import dev.motionfusion.core.replay.Replayer;
import dev.motionfusion.core.event.SensorEvents;
import dev.motionfusion.core.session.SessionMetadata;
import dev.motionfusion.core.session.SessionWriter;
import dev.motionfusion.core.sim.MotionSimulator;
import dev.motionfusion.core.sim.SimulatedSample;
import dev.motionfusion.core.sim.SimulationSettings;
import java.io.IOException;
import java.io.OutputStream;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.Comparator;
import java.util.List;
import java.util.concurrent.TimeUnit;
import java.util.stream.Stream;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Param;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Warmup;

@State(Scope.Benchmark)
@BenchmarkMode(Mode.SingleShotTime)
@OutputTimeUnit(TimeUnit.MILLISECONDS)
@Warmup(iterations = 2)
@Measurement(iterations = 5)
@Fork(value = 1, jvmArgs = {"-Xmx256m"})
public class ReplayBenchmark {
    /** Rows in the session: 3 sensors × 200 Hz × 3600 s. */
    public static final long ROWS = 3L * 200 * 3600;

    /** csv: format the replay CSV into a discarding stream; none: filter only, no output. */
    @Param({"csv", "none"})
    public String output;

    private Path dir;

    @Setup(Level.Trial)
    public void writeSession() throws IOException {
        dir = Files.createTempDirectory("replay-bench").resolve("session");
        writeHourSession(dir);
    }

    /**
     * One simulated minute at 200 Hz, repeated 60 times with advancing timestamps (the motion
     * jumps at each repetition; that costs nothing extra).
     */
    public static void writeHourSession(Path dir) throws IOException {
        SimulationSettings s = new SimulationSettings();
        List<SimulatedSample> minute = new MotionSimulator(s).run();
        try (SessionWriter w = SessionWriter.create(dir, new SessionMetadata())) {
            long period = 5_000_000L;
            for (int rep = 0; rep < 60; rep++) {
                long base = 10_000_000_000L + rep * 60_000_000_000L;
                for (int k = 0; k < minute.size(); k++) {
                    SimulatedSample x = minute.get(k);
                    long t = base + k * period;
                    w.accelerometer(t, (float) x.getAcc().getX(), (float) x.getAcc().getY(), (float) x.getAcc().getZ(), 3);
                    w.magnetometer(t + 1_000, (float) x.getMag().getX(), (float) x.getMag().getY(), (float) x.getMag().getZ(), 3);
                    w.gyroscope(t + 2_000, (float) x.getGyro().getX(), (float) x.getGyro().getY(), (float) x.getGyro().getZ(), 3);
                }
            }
        }
    }

    @TearDown(Level.Trial)
    public void delete() throws IOException {
        try (Stream<Path> files = Files.walk(dir.getParent())) {
            files.sorted(Comparator.reverseOrder()).forEach(p -> p.toFile().delete());
        }
    }

    @Benchmark
    public long replay() throws IOException {
        return replay(dir, "csv".equals(output));
    }

    /** Replays the session at [dir]; returns the events read. */
    public static long replay(Path dir, boolean csv) throws IOException {
        ReplayCounts counts = run(dir, csv);
        if (counts.getEvents() != ROWS) throw new IllegalStateException("read " + counts.getEvents() + " rows, expected " + ROWS);
        return counts.getEvents();
    }

    /** Replays the recording at [input] with the default settings, into a discarding CSV ([csv]) or no output. */
    public static ReplayCounts run(Path input, boolean csv) throws IOException {
        try (Recording rec = Recording.open(input); SensorEvents events = rec.events(rec.getStreams())) {
            Replayer replayer = new Replayer(new FilterSettings());
            if (csv) {
                try (ReplayCsvWriter writer = new ReplayCsvWriter(OutputStream.nullOutputStream(), true)) {
                    return replayer.run(events, rec.getOriginNs(), writer, null);
                }
            }
            return replayer.run(events, rec.getOriginNs(), new ReplayListener() {
                double sink;
                @Override public void step(ReplayStep step) { sink += step.getOrientation()[0]; }
            }, null);
        }
    }

    /**
     * The CPU-time check beside JMH, for shared machines where wall-clock time measures the load:
     * writes the session, replays it 7 times with and without CSV output, and prints wall-clock
     * and thread CPU time per replay (the thread's CPU time excludes JIT and GC threads, and the
     * threads a replay starts on a machine with two or more cores).
     * Run: java -Xmx64m -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.ReplayBenchmark
     */
    public static void main(String[] args) throws IOException {
        Path d = Files.createTempDirectory("replay-bench").resolve("session");
        long t0 = System.nanoTime();
        writeHourSession(d);
        System.out.printf("wrote %,d rows in %.1f s (%.0f ns per row)%n", ROWS, (System.nanoTime() - t0) / 1e9, (System.nanoTime() - t0) / (double) ROWS);
        printCpuTimes(7, ROWS, csv -> replay(d, csv));
        try (Stream<Path> files = Files.walk(d.getParent())) {
            files.sorted(Comparator.reverseOrder()).forEach(p -> p.toFile().delete());
        }
    }

    /** One whole replay, with CSV output or without. */
    interface Replay {
        void run(boolean csv) throws IOException;
    }

    /** Runs [replay] [runs] times with and without CSV output; prints wall clock, thread CPU time and heap per replay of [rows] rows. */
    static void printCpuTimes(int runs, long rows, Replay replay) throws IOException {
        java.lang.management.ThreadMXBean mx = java.lang.management.ManagementFactory.getThreadMXBean();
        for (int i = 0; i < runs; i++) {
            for (boolean csv : new boolean[] {true, false}) {
                long t = System.nanoTime();
                long c = mx.getCurrentThreadCpuTime();
                replay.run(csv);
                double cpu = (mx.getCurrentThreadCpuTime() - c) / 1e9;
                double s = (System.nanoTime() - t) / 1e9;
                Runtime rt = Runtime.getRuntime();
                System.out.printf("replay %d %-4s: wall %.2f s (%.2f M rows/s), CPU %.2f s (%.2f M rows/s), heap used %.0f MB%n",
                    i, csv ? "csv" : "none", s, rows / s / 1e6, cpu, rows / cpu / 1e6, (rt.totalMemory() - rt.freeMemory()) / 1e6);
            }
        }
    }
}
