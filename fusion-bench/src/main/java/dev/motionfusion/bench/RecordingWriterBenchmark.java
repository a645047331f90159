/*
 * JMH benchmark of the app's capture path per sensor event while recording: the sensor thread's
 * copy into the ring (EventRing.offer) plus the capture thread's share (drain, reorder window,
 * the one live Madgwick filter, the session CSV row through SessionWriter and the orientation
 * row), all seven sensor streams in turn. Run: java -jar fusion-bench/target/benchmarks.jar RecordingWriter -prof gc
 * "file" writes real files in a temporary folder; "devnull" points the stream files at
 * /dev/null (Linux) to leave the storage out. Issue 7's budget: at most 1 µs per event.
 */
package dev.motionfusion.bench;

import dev.motionfusion.app.fusion.Capture;
import dev.motionfusion.app.record.CoreSessionFormat;
import dev.motionfusion.app.record.Recorder;
import dev.motionfusion.app.sensor.EventRing;
import dev.motionfusion.app.sensor.SensorStreams;
import dev.motionfusion.core.session.SessionMetadata;
import dev.motionfusion.core.event.SessionStream;
import java.io.IOException;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.Paths;
import java.util.Comparator;
import java.util.concurrent.TimeUnit;
import java.util.stream.Stream;
import kotlin.Unit;
import org.openjdk.jmh.annotations.Benchmark;
import org.openjdk.jmh.annotations.BenchmarkMode;
import org.openjdk.jmh.annotations.Fork;
import org.openjdk.jmh.annotations.Level;
import org.openjdk.jmh.annotations.Measurement;
import org.openjdk.jmh.annotations.Mode;
import org.openjdk.jmh.annotations.OperationsPerInvocation;
import org.openjdk.jmh.annotations.OutputTimeUnit;
import org.openjdk.jmh.annotations.Param;
import org.openjdk.jmh.annotations.Scope;
import org.openjdk.jmh.annotations.Setup;
import org.openjdk.jmh.annotations.State;
import org.openjdk.jmh.annotations.TearDown;
import org.openjdk.jmh.annotations.Warmup;

@State(Scope.Thread)
@BenchmarkMode(Mode.AverageTime)
@OutputTimeUnit(TimeUnit.NANOSECONDS)
@Warmup(iterations = 5, time = 1)
@Measurement(iterations = 5, time = 1)
@Fork(1)
public class RecordingWriterBenchmark {
    @Param({"file", "devnull"})
    public String target;

    private static final int BATCH = 1024;
    private final float[] values = {0.1f, 0.2f, 9.8f, 0.01f, 0.02f, 0.03f};
    private SessionStream[] streams;
    private Path dir;
    private EventRing ring;
    private Capture capture;
    private Recorder recorder;
    private long t = 1_000_000_000L;
    private int next;

    @Setup(Level.Iteration)
    public void open() throws IOException {
        streams = SensorStreams.INSTANCE.getAll().toArray(new SessionStream[0]);
        dir = Files.createTempDirectory("writer-bench");
        if (target.equals("devnull")) {
            for (SessionStream s : SessionStream.values()) Files.createSymbolicLink(dir.resolve(s.getFileName()), Paths.get("/dev/null"));
        }
        ring = new EventRing(1 << 16);
        capture = FloodCapture.manual(ring);
        recorder = new Recorder(CoreSessionFormat.INSTANCE.create(dir.toFile(), new SessionMetadata()), r -> Unit.INSTANCE,
            500_000_000L, () -> Long.MAX_VALUE, 0L, 2_000_000_000L, 100_000_000L, null, 60_000_000_000L, null, Long.MIN_VALUE);
        FloodCapture.attach(capture, recorder);
    }

    @TearDown(Level.Iteration)
    public void close() throws IOException {
        FloodCapture.detach(capture, recorder);
        try (Stream<Path> files = Files.walk(dir)) {
            files.sorted(Comparator.reverseOrder()).forEach(p -> p.toFile().delete());
        }
    }

    /** BATCH events offered by the "sensor thread", then written by the "writer": time per event. */
    @Benchmark
    @OperationsPerInvocation(BATCH)
    public int offerAndWrite() {
        for (int i = 0; i < BATCH; i++) {
            SessionStream s = streams[next];
            next = next == streams.length - 1 ? 0 : next + 1;
            t += 300_000L;
            ring.offer(s, t, 3, values, s.getValueCount());
        }
        return FloodCapture.pump(capture);
    }
}
