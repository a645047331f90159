/*
 * Benchmark of `fusion allan`'s work on a 1-hour, 200 Hz session (the replay benchmark's
 * session: accelerometer, gyroscope, magnetometer, 2,160,000 rows): read and merge the files and
 * accumulate the overlapping Allan deviation of the gyroscope and the accelerometer (720,000
 * samples each), then fit the noise terms. One operation = one whole analysis.
 * Run: java -jar fusion-bench/target/benchmarks.jar AllanBenchmark  (see docs/BENCHMARKS.md).
 */
package dev.motionfusion.bench;

import dev.motionfusion.core.calib.AllanResult;
import dev.motionfusion.core.input.Recording;
import dev.motionfusion.core.event.SensorEvents;
import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.Comparator;
import java.util.concurrent.TimeUnit;
import java.util.stream.Stream;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OutputTimeUnit;
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
@Fork(value = 1, jvmArgs = {"-Xmx32m"})
public class AllanBenchmark {
    private Path dir;

    @Setup(Level.Trial)
    public void writeSession() throws IOException {
        dir = Files.createTempDirectory("allan-bench").resolve("session");
        ReplayBenchmark.writeHourSession(dir);
    }

    @TearDown(Level.Trial)
    public void delete() throws IOException {
        deleteTree(dir.getParent());
    }

    /** Deletes [root] and everything below it. */
    static void deleteTree(Path root) throws IOException {
        try (Stream<Path> files = Files.walk(root)) {
            files.sorted(Comparator.reverseOrder()).forEach(p -> p.toFile().delete());
        }
    }

    @Benchmark
    public double allan() throws IOException {
        return allan(dir);
    }

    /** The Allan analysis of the session at [dir], as `fusion allan` runs it; returns a figure so nothing is optimised away. */
    public static double allan(Path dir) throws IOException {
        try (Recording rec = Recording.open(dir); SensorEvents events = rec.events(rec.getStreams())) {
            AllanResult r = AllanResult.run(events, rec.getStreams(), null);
            if (r.getGyroscope() == null || r.getGyroscope().getSamples() != 720_000L) throw new IllegalStateException("expected 720,000 gyroscope samples");
            return r.getGyroscopeTerms().get(0).getWhiteNoise() + r.getAccelerometerTerms().get(0).getWhiteNoise();
        }
    }

    /**
     * Wall-clock and thread CPU time per analysis, and the heap in use after it, for shared machines.
     * Run: java -Xmx32m -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.AllanBenchmark
     */
    public static void main(String[] args) throws IOException {
        java.lang.management.ThreadMXBean mx = java.lang.management.ManagementFactory.getThreadMXBean();
        Path d = Files.createTempDirectory("allan-bench").resolve("session");
        ReplayBenchmark.writeHourSession(d);
        try {
            for (int i = 0; i < 7; i++) {
                long t = System.nanoTime();
                long c = mx.getCurrentThreadCpuTime();
                allan(d);
                double cpu = (mx.getCurrentThreadCpuTime() - c) / 1e9;
                double s = (System.nanoTime() - t) / 1e9;
                Runtime rt = Runtime.getRuntime();
                System.gc();
                System.out.printf("allan of 1 h at 200 Hz: %.2f s wall, %.2f s thread CPU, heap in use after %.1f MB (max %.0f MB)%n",
                    s, cpu, (rt.totalMemory() - rt.freeMemory()) / 1e6, rt.maxMemory() / 1e6);
            }
        } finally {
            deleteTree(d.getParent());
        }
    }
}
