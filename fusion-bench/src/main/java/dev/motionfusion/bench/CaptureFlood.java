/*
 * The flood target of the app's capture path (issue 13): 1,000,000 events over the seven sensor
 * streams, delivered as Android does (each stream's batch in turn) far faster than a phone's
 * fastest rate, through the ring, the reorder window, the live filter and the recorder into a
 * real session on disk, with the capture's own thread. Reports events lost (refused by the
 * ring), rows written, the heap before and after, and the wall time.
 * Run: java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.CaptureFlood [events/s]
 */
package dev.motionfusion.bench;

import dev.motionfusion.app.fusion.Capture;
import dev.motionfusion.app.record.CoreSessionFormat;
import dev.motionfusion.app.record.Recorder;
import dev.motionfusion.app.record.RecorderResult;
import dev.motionfusion.app.sensor.EventRing;
import dev.motionfusion.app.sensor.SensorStreams;
import dev.motionfusion.core.session.SessionMetadata;
import dev.motionfusion.core.event.SessionStream;
import java.lang.management.ManagementFactory;
import java.lang.management.MemoryMXBean;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.Comparator;
import java.util.concurrent.atomic.AtomicReference;
import java.util.concurrent.locks.LockSupport;
import java.util.stream.Stream;
import kotlin.Unit;

public final class CaptureFlood {
    private CaptureFlood() {}

    public static void main(String[] args) throws Exception {
        double rate = args.length > 0 ? Double.parseDouble(args[0]) : 150_000.0; // ~40x seven streams at 500 Hz
        int total = 1_000_006; // 7 streams x 142,858
        SessionStream[] streams = SensorStreams.INSTANCE.getAll().toArray(new SessionStream[0]);
        Path dir = Files.createTempDirectory("capture-flood");
        MemoryMXBean mem = ManagementFactory.getMemoryMXBean();
        EventRing ring = new EventRing(Capture.DEFAULT_RING_CAPACITY);
        Capture capture = FloodCapture.threaded(ring);
        AtomicReference<RecorderResult> ended = new AtomicReference<>();
        Recorder recorder = new Recorder(CoreSessionFormat.INSTANCE.create(dir.resolve("s").toFile(), new SessionMetadata()),
            r -> { ended.set(r); return Unit.INSTANCE; }, 500_000_000L, () -> Long.MAX_VALUE, 0L, 2_000_000_000L, 100_000_000L, null, 60_000_000_000L, null, Long.MIN_VALUE);
        FloodCapture.attach(capture, recorder);
        System.gc();
        long heapBefore = mem.getHeapMemoryUsage().getUsed();
        long heapPeak = heapBefore;
        float[] v = {0.1f, 0.2f, 9.8f, 0.01f, 0.02f, 0.03f};
        int batch = 8;
        long t = 1_000_000_000L;
        long periodNs = 2_000_000L; // each stream at 500 Hz in sensor time
        long start = System.nanoTime();
        int offered = 0;
        int maxQueued = 0;
        while (offered < total) {
            for (SessionStream s : streams) {
                for (int k = 0; k < batch && offered < total; k++, offered++) ring.offer(s, t + k * periodNs, 3, v, s.getValueCount());
            }
            t += batch * periodNs;
            maxQueued = Math.max(maxQueued, ring.getSize());
            long due = start + (long) (offered / rate * 1e9);
            while (System.nanoTime() < due) LockSupport.parkNanos(50_000L);
            if ((offered & 0xffff) < batch * streams.length) heapPeak = Math.max(heapPeak, mem.getHeapMemoryUsage().getUsed());
        }
        long produced = System.nanoTime() - start;
        while (ring.getSize() > 0) LockSupport.parkNanos(1_000_000L);
        FloodCapture.detach(capture, recorder);
        while (ended.get() == null) LockSupport.parkNanos(1_000_000L);
        long wall = System.nanoTime() - start;
        capture.release();
        System.gc();
        long heapAfter = mem.getHeapMemoryUsage().getUsed();
        RecorderResult r = ended.get();
        System.out.printf("capture flood: %,d events over %d streams offered in %.2f s (%.0f events/s), done in %.2f s%n",
            offered, streams.length, produced / 1e9, offered / (produced / 1e9), wall / 1e9);
        System.out.printf("  lost (refused by the ring): %,d; raw rows written: %,d; fused rows: %,d; end: %s%n",
            capture.getRefusedEvents(), r.getRows(), r.getFusedRows(), r.getEnd());
        System.out.printf("  late (outside the reorder window): %,d; most events queued at once: %,d of %,d%n",
            capture.getLateEvents(), maxQueued, ring.getCapacity());
        System.out.printf("  heap in use: %.1f MB before, %.1f MB peak sampled, %.1f MB after (after GC)%n",
            heapBefore / 1e6, heapPeak / 1e6, heapAfter / 1e6);
        try (Stream<Path> files = Files.walk(dir)) {
            files.sorted(Comparator.reverseOrder()).forEach(p -> p.toFile().delete());
        }
        if (capture.getRefusedEvents() != 0 || r.getRows() != offered) System.exit(1);
    }
}
