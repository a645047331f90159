/*
 * The live stream end to end on loopback: the phone's StreamServer and the laptop's StreamClient in one
 * process, seven sensor streams at 200 Hz plus the orientation (1,600 messages a second), paced in real
 * time as a phone would produce them. Reports the latency from publish to the client's callback (one
 * clock, System.nanoTime, for both ends: no clock offset in it), median and p99, the messages lost, and
 * the process's CPU time per 1,000 messages (server and client together).
 * Run: java -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.StreamLatency [SECONDS]
 */
package dev.motionfusion.bench;

import dev.motionfusion.core.event.SessionStream;
import dev.motionfusion.core.session.SessionMetadata;
import dev.motionfusion.core.stream.StreamMessage;
import dev.motionfusion.stream.StreamClient;
import dev.motionfusion.stream.StreamOffer;
import dev.motionfusion.stream.StreamServer;
import dev.motionfusion.stream.StreamServerSettings;
import java.lang.management.ManagementFactory;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.URI;
import java.util.Arrays;
import java.util.List;
import java.util.Locale;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.locks.LockSupport;

public final class StreamLatency {
    /** The seven sensor streams a phone streams, published by [publishRealTime]. */
    static final List<SessionStream> STREAMS = List.of(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE,
        SessionStream.MAGNETOMETER, SessionStream.GYROSCOPE_UNCALIBRATED, SessionStream.MAGNETOMETER_UNCALIBRATED,
        SessionStream.ROTATION_VECTOR, SessionStream.GAME_ROTATION_VECTOR);

    public static void main(String[] args) throws Exception {
        int seconds = args.length > 0 ? Integer.parseInt(args[0]) : 30;
        List<SessionStream> offered = new java.util.ArrayList<>(STREAMS);
        offered.add(SessionStream.ORIENTATION);
        StreamOffer offer = new StreamOffer("bench", new SessionMetadata(), offered);
        StreamServer server = new StreamServer(new InetSocketAddress(InetAddress.getLoopbackAddress(), 0), "1", () -> offer,
            new StreamServerSettings());
        server.start();
        int total = seconds * 200 * 8;
        long[] latency = new long[total];
        AtomicInteger received = new AtomicInteger();
        StreamClient client = new StreamClient(new URI("ws://127.0.0.1:" + server.getPort()), new StreamMessage.Pair("1", null, null, 1), m -> {
            long now = System.nanoTime();
            long t;
            if (m instanceof StreamMessage.Sample) t = ((StreamMessage.Sample) m).getTimestampNs();
            else if (m instanceof StreamMessage.Orientation) t = ((StreamMessage.Orientation) m).getTimestampNs();
            else return kotlin.Unit.INSTANCE;
            int i = received.getAndIncrement();
            if (i < latency.length) latency[i] = now - t;
            return kotlin.Unit.INSTANCE;
        });
        client.connect(10_000);
        com.sun.management.OperatingSystemMXBean os = (com.sun.management.OperatingSystemMXBean) ManagementFactory.getOperatingSystemMXBean();
        // Warm-up: two seconds, not counted.
        publishRealTime(server, 2);
        while (received.get() < 2 * 1600) LockSupport.parkNanos(1_000_000);
        received.set(0);
        long cpu0 = os.getProcessCpuTime();
        java.util.Map<String, Long> threads0 = threadCpu();
        publishRealTime(server, seconds);
        long deadline = System.nanoTime() + 5_000_000_000L;
        while (received.get() < total && System.nanoTime() < deadline) LockSupport.parkNanos(1_000_000);
        long cpu = os.getProcessCpuTime() - cpu0;
        java.util.Map<String, Long> threads1 = threadCpu();
        long serverCpu = 0;
        long clientCpu = 0;
        for (java.util.Map.Entry<String, Long> e : threads1.entrySet()) {
            long d = e.getValue() - threads0.getOrDefault(e.getKey(), 0L);
            String name = e.getKey();
            if (name.startsWith("stream-sender") || name.startsWith("WebSocketSelector") || name.startsWith("WebSocketWorker")) serverCpu += d;
            else if (name.startsWith("WebSocketConnectReadThread") || name.startsWith("WebSocketWriteThread")) clientCpu += d;
        }
        int n = Math.min(received.get(), total);
        long[] sorted = Arrays.copyOf(latency, n);
        Arrays.sort(sorted);
        System.out.printf(Locale.ROOT, "%d s, %d messages published, %d received (%d lost, %d dropped by the server)%n",
            seconds, total, n, total - n, server.getHandOffDroppedCount());
        System.out.printf(Locale.ROOT, "latency publish -> client callback: median %.3f ms, p99 %.3f ms, max %.3f ms%n",
            sorted[n / 2] / 1e6, sorted[Math.min(n - 1, (int) (n * 0.99))] / 1e6, sorted[n - 1] / 1e6);
        System.out.printf(Locale.ROOT, "CPU (server and client, whole process): %.1f ms per 1,000 messages, %.1f %% of one core%n",
            cpu / 1e6 / (n / 1000.0), 100.0 * cpu / (seconds * 1e9));
        System.out.printf(Locale.ROOT, "  the phone's side (sender, selector and worker threads): %.1f ms per 1,000 messages; the client's reading: %.1f ms%n",
            serverCpu / 1e6 / (n / 1000.0), clientCpu / 1e6 / (n / 1000.0));
        client.close();
        server.stop(1000);
    }

    /** CPU time of every live thread by name (name plus id, so that two threads of one name are kept apart). */
    private static java.util.Map<String, Long> threadCpu() {
        java.lang.management.ThreadMXBean bean = ManagementFactory.getThreadMXBean();
        java.util.Map<String, Long> out = new java.util.HashMap<>();
        for (java.lang.management.ThreadInfo info : bean.dumpAllThreads(false, false)) {
            long t = bean.getThreadCpuTime(info.getThreadId());
            if (t >= 0) out.put(info.getThreadName() + "#" + info.getThreadId(), t);
        }
        return out;
    }

    /** Publishes [seconds] of the seven streams at 200 Hz and the orientation, in real time; timestamps are System.nanoTime. */
    static void publishRealTime(StreamServer server, int seconds) {
        long start = System.nanoTime();
        float[] v = new float[6];
        for (int k = 0; k < seconds * 200; k++) {
            long due = start + k * 5_000_000L;
            long wait;
            while ((wait = due - System.nanoTime()) > 0) LockSupport.parkNanos(wait);
            for (SessionStream s : STREAMS) {
                v[0] = k * 1e-3f;
                server.publishSample(s, System.nanoTime(), v, 3);
            }
            server.publishOrientation(System.nanoTime(), 1.0, 0.0, 0.0, 0.0);
        }
    }
}
