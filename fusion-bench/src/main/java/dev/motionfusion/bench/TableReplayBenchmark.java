/*
 * JMH benchmark of `fusion replay TABLE.csv` without the JVM start: a plain 9D IMU table of
 * 2,199,600 rows (`fusion simulate --duration 3600 --rate 611 -o TABLE.csv`, 239 MB), read through the byte tokenizer, filtered with the defaults, and
 * formatted with the default 14 output columns into a discarding stream (`csv`), or filtered only
 * (`none`). One operation = one whole replay; rows/s = 2,199,600 / (s/op).
 * Run: java -jar fusion-bench/target/benchmarks.jar TableReplayBenchmark -p table=TABLE.csv  (see docs/BENCHMARKS.md).
 */
package dev.motionfusion.bench;

import java.io.IOException;
import java.nio.file.Path;
import java.nio.file.Paths;
import java.util.concurrent.TimeUnit;
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
import org.openjdk.jmh.annotations.Warmup;

@State(Scope.Benchmark)
@BenchmarkMode(Mode.SingleShotTime)
@OutputTimeUnit(TimeUnit.MILLISECONDS)
@Warmup(iterations = 2)
@Measurement(iterations = 5)
@Fork(value = 1, jvmArgs = {"-Xmx256m"})
public class TableReplayBenchmark {
    /** Rows of the table: 611 Hz for 3600 s. */
    public static final long ROWS = 611L * 3600;

    /** csv: the default 14 output columns into a discarding stream; none: filter only. */
    @Param({"csv", "none"})
    public String output;

    /** The table, made by `fusion simulate --duration 3600 --rate 611 -o TABLE.csv` (run with -p table=TABLE.csv). */
    @Param({""})
    public String table;

    private Path file;

    @Setup(Level.Trial)
    public void open() {
        if (table.isEmpty()) throw new IllegalArgumentException("give the table: -p table=TABLE.csv (fusion simulate --duration 3600 --rate 611 -o TABLE.csv)");
        file = Paths.get(table);
    }

    @Benchmark
    public long replay() throws IOException {
        return replay(file, "csv".equals(output));
    }

    /** Replays the table at [file]; returns the rows read. */
    public static long replay(Path file, boolean csv) throws IOException {
        long rows = ReplayBenchmark.run(file, csv).getGyroscope();
        if (rows != ROWS) throw new IllegalStateException("read " + rows + " rows, expected " + ROWS);
        return rows;
    }

    /**
     * The CPU-time check beside JMH: replays the table given as the argument 5 times with and
     * without output and prints wall-clock and thread CPU time per replay (the calling thread's:
     * with two or more cores the table is parsed on a second one, not counted here).
     * Run: java -Xmx64m -XX:ActiveProcessorCount=1 -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.TableReplayBenchmark TABLE.csv
     */
    public static void main(String[] args) throws IOException {
        Path t = Paths.get(args[0]);
        ReplayBenchmark.printCpuTimes(5, ROWS, csv -> replay(t, csv));
    }
}
