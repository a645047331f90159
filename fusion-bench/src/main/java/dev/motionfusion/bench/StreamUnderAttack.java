/*
 * The live stream while someone on the network misbehaves (docs/STREAMING.md, "Security"): the phone's StreamServer and
 * one paired laptop (StreamClient) in one process on loopback, seven streams at 200 Hz plus the orientation (1,600
 * messages a second) paced in real time, while one attack at a time runs from raw sockets on 127/8 addresses. For each:
 * the paired client's messages kept and its latency (publish to callback, one clock), the heap retained after a
 * collection with the attack's connections still open, and how long a laptop takes to pair at the attack's end (from
 * 127.0.0.1, which the paired client's address: during a pause after wrong codes only such an address may pair).
 * Every attack loop is bounded by the run's time and a count, and ends by itself.
 * The server asks its "phone" to confirm each new client, as the app's does: this one allows 127.0.0.1 (the laptops
 * measured here) and denies every other address. Against a server without that (an older fusion-stream on the class
 * path, whose StreamServer has only the three-argument constructor) it runs the same attacks without it, which is how
 * the "before" figures in docs/STREAMING.md were taken.
 * Run: java -Xmx256m [-DnoConfirmation=true] -cp fusion-bench/target/benchmarks.jar dev.motionfusion.bench.StreamUnderAttack [SECONDS_PER_ATTACK [ATTACK,...]]
 * (ATTACK: none, frames, headers, halfopen, places, rotating, preopened, origin, binary; default all).
 */
package dev.motionfusion.bench;

import dev.motionfusion.core.event.SessionStream;
import dev.motionfusion.core.session.SessionMetadata;
import dev.motionfusion.core.stream.StreamMessage;
import dev.motionfusion.stream.StreamClient;
import dev.motionfusion.stream.StreamOffer;
import dev.motionfusion.stream.StreamServer;
import dev.motionfusion.stream.StreamServerSettings;
import java.io.ByteArrayOutputStream;
import java.io.IOException;
import java.io.InputStream;
import java.io.OutputStream;
import java.lang.management.ManagementFactory;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.Socket;
import java.net.URI;
import java.nio.charset.StandardCharsets;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.Locale;
import java.util.concurrent.atomic.AtomicBoolean;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicLong;
import java.util.concurrent.locks.LockSupport;

public final class StreamUnderAttack {
    private static final String CODE = "482913";
    private static final String REQUEST = "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        + "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";

    /** One attack: runs until [stop] is set or its own bound, from its own threads; returns what it counted. */
    private interface Attack {
        String run(int port, AtomicBoolean stop, List<Socket> held) throws Exception;
    }

    public static void main(String[] args) throws Exception {
        int seconds = args.length > 0 ? Integer.parseInt(args[0]) : 10;
        List<SessionStream> offered = new ArrayList<>(StreamLatency.STREAMS);
        offered.add(SessionStream.ORIENTATION);
        StreamOffer offer = new StreamOffer("bench", new SessionMetadata(), offered);
        System.out.printf(Locale.ROOT, "%d s per attack, 1,600 messages/s to one paired client, loopback%n%n", seconds);
        System.out.println("| attack | paired client's messages kept | p99 latency | heap retained | a new laptop pairs in | attack's own count |");
        System.out.println("|---|---|---|---|---|---|");
        Object[][] attacks = {
            {"none", "none", (Attack) (port, stop, held) -> ""},
            {"frames", "2 GiB frame headers, again and again", (Attack) StreamUnderAttack::bigFrames},
            {"headers", "endless upgrade headers, 2 connections", (Attack) StreamUnderAttack::endlessHeaders},
            {"halfopen", "500 half-open upgrade requests", (Attack) StreamUnderAttack::halfOpen},
            {"places", "24 connections holding places without a code", (Attack) (port, stop, held) -> holdPlaces(port, stop, held, 2, "", null)},
            {"rotating", "wrong codes from 200 rotating 127.x addresses", (Attack) StreamUnderAttack::guessing},
            {"preopened", "8 connections opened, then 8 wrong codes at once, again and again", (Attack) StreamUnderAttack::preOpened},
            {"origin", "24 browser pages of a foreign Origin holding places", (Attack) (port, stop, held) ->
                holdPlaces(port, stop, held, 5, "Origin: http://attacker.example\r\n", null)},
            {"binary", "24 connections whose first frame is binary (the right code)", (Attack) (port, stop, held) ->
                holdPlaces(port, stop, held, 6, "", frame(2, pairJson(CODE)))},
        };
        List<String> wanted = args.length > 1 ? Arrays.asList(args[1].split(",")) : null;
        for (Object[] a : attacks) {
            if (wanted == null || wanted.contains((String) a[0])) measure(offer, (String) a[1], (Attack) a[2], seconds);
        }
    }

    /**
     * The server: one whose phone confirms each new client (allowing 127.0.0.1, denying the rest) where the class path's
     * fusion-stream has it, else the older three-argument one.
     */
    private static StreamServer newServer(StreamOffer offer, AtomicInteger codeChanges) {
        InetSocketAddress address = new InetSocketAddress(InetAddress.getLoopbackAddress(), 0);
        StreamServer[] self = new StreamServer[1];
        try {
            if (Boolean.getBoolean("noConfirmation")) throw new NoSuchMethodError("-DnoConfirmation=true");
            self[0] = new StreamServer(address, CODE, () -> offer, new StreamServerSettings(), System::nanoTime, () -> CODE,
                c -> { codeChanges.incrementAndGet(); return kotlin.Unit.INSTANCE; }, f -> kotlin.Unit.INSTANCE,
                request -> {
                    if (request.getAddress().equals("127.0.0.1")) self[0].allow(request.getId());
                    else self[0].deny(request.getId());
                    return kotlin.Unit.INSTANCE;
                });
            confirming = true;
        } catch (NoSuchMethodError | NoClassDefFoundError e) {
            self[0] = new StreamServer(address, CODE, () -> offer);
            confirming = false;
        }
        return self[0];
    }

    private static boolean confirming;

    private static void measure(StreamOffer offer, String name, Attack attack, int seconds) throws Exception {
        AtomicInteger codeChanges = new AtomicInteger();
        StreamServer server = newServer(offer, codeChanges);
        server.start();
        int total = seconds * 200 * 8;
        long[] latency = new long[total];
        AtomicInteger received = new AtomicInteger();
        AtomicBoolean counting = new AtomicBoolean();
        StreamClient client = new StreamClient(new URI("ws://127.0.0.1:" + server.getPort()), new StreamMessage.Pair(CODE, null, null, 1), m -> {
            long now = System.nanoTime();
            long t;
            if (m instanceof StreamMessage.Sample) t = ((StreamMessage.Sample) m).getTimestampNs();
            else if (m instanceof StreamMessage.Orientation) t = ((StreamMessage.Orientation) m).getTimestampNs();
            else return kotlin.Unit.INSTANCE;
            if (!counting.get()) return kotlin.Unit.INSTANCE;
            int i = received.getAndIncrement();
            if (i < latency.length) latency[i] = now - t;
            return kotlin.Unit.INSTANCE;
        });
        client.connect(10_000);
        if (!headerPrinted) {
            headerPrinted = true;
            System.out.println(confirming ? "(server: new clients confirmed on the phone)" : "(server: without confirmation on the phone)");
        }
        StreamLatency.publishRealTime(server, 1); // warm-up
        System.gc();
        long heap0 = usedHeap();
        AtomicBoolean stop = new AtomicBoolean();
        List<Socket> held = java.util.Collections.synchronizedList(new ArrayList<>());
        String[] count = {""};
        Thread attacker = new Thread(() -> {
            try {
                count[0] = attack.run(server.getPort(), stop, held);
            } catch (Exception e) {
                count[0] = "attack ended: " + e;
            }
        }, "attack");
        counting.set(true);
        attacker.start();
        StreamLatency.publishRealTime(server, seconds);
        long deadline = System.nanoTime() + 3_000_000_000L;
        while (received.get() < total && System.nanoTime() < deadline) LockSupport.parkNanos(1_000_000);
        counting.set(false);
        // A new laptop, while the attack still runs.
        long t0 = System.nanoTime();
        String pairs;
        try (StreamClient laptop = new StreamClient(new URI("ws://127.0.0.1:" + server.getPort()), new StreamMessage.Pair(CODE, null, null, 1), m -> kotlin.Unit.INSTANCE)) {
            laptop.connect(10_000);
            pairs = String.format(Locale.ROOT, "%.0f ms", (System.nanoTime() - t0) / 1e6);
        } catch (Exception e) {
            pairs = "no: " + e.getMessage();
        }
        System.gc();
        long heap = usedHeap() - heap0;
        stop.set(true);
        attacker.join(10_000);
        synchronized (held) {
            for (Socket s : held) try { s.close(); } catch (IOException ignored) { }
        }
        int n = Math.min(received.get(), total);
        long[] sorted = Arrays.copyOf(latency, n);
        Arrays.sort(sorted);
        String p99 = n == 0 ? "-" : String.format(Locale.ROOT, "%.1f ms", sorted[Math.min(n - 1, (int) (n * 0.99))] / 1e6);
        String extra = count[0] + (codeChanges.get() > 0 ? " (" + codeChanges.get() + " new code(s): at most 5 codes looked at per pause)" : "");
        System.out.printf(Locale.ROOT, "| %s | %.2f %% (%d of %d) | %s | %+.1f MB | %s | %s |%n",
            name, 100.0 * n / total, n, total, p99, heap / 1e6, pairs, extra);
        client.close();
        server.stop(1000);
    }

    private static boolean headerPrinted;

    private static long usedHeap() {
        return ManagementFactory.getMemoryMXBean().getHeapMemoryUsage().getUsed();
    }

    private static Socket connect(int port, String local) throws IOException {
        Socket s = new Socket();
        s.bind(new InetSocketAddress(local, 0));
        s.connect(new InetSocketAddress(InetAddress.getLoopbackAddress(), port), 5_000);
        s.setSoTimeout(5_000);
        return s;
    }

    private static boolean upgrade(Socket s) throws IOException {
        return upgrade(s, "");
    }

    /** Sends the upgrade request with [extra] header lines; true when the server switched protocols. */
    private static boolean upgrade(Socket s, String extra) throws IOException {
        s.getOutputStream().write((REQUEST.substring(0, REQUEST.length() - 2) + extra + "\r\n").getBytes(StandardCharsets.US_ASCII));
        InputStream in = s.getInputStream();
        ByteArrayOutputStream head = new ByteArrayOutputStream();
        while (!head.toString(StandardCharsets.US_ASCII).endsWith("\r\n\r\n")) {
            int b = in.read();
            if (b < 0 || head.size() > 65_536) return false;
            head.write(b);
        }
        return head.toString(StandardCharsets.US_ASCII).startsWith("HTTP/1.1 101");
    }

    /** Reads until the server closes (bounded by the socket's timeout). */
    private static void drain(Socket s) {
        try {
            InputStream in = s.getInputStream();
            byte[] buf = new byte[4096];
            for (int k = 0; k < 10_000 && in.read(buf) >= 0; k++) { }
        } catch (IOException ignored) {
        }
    }

    private static String bigFrames(int port, AtomicBoolean stop, List<Socket> held) throws IOException {
        byte[] header = {(byte) 0x81, (byte) 0xff, 0, 0, 0, 0, 0x7f, (byte) 0xff, (byte) 0xff, (byte) 0xff, 0, 0, 0, 0};
        int sent = 0;
        while (!stop.get() && sent < 100_000) {
            try (Socket s = connect(port, "127.0.0.2")) {
                if (!upgrade(s)) continue;
                s.getOutputStream().write(header);
                sent++;
                drain(s);
            }
        }
        return sent + " headers";
    }

    private static String endlessHeaders(int port, AtomicBoolean stop, List<Socket> held) throws Exception {
        AtomicLong bytes = new AtomicLong();
        AtomicInteger cut = new AtomicInteger();
        List<Thread> threads = new ArrayList<>();
        for (int t = 0; t < 2; t++) {
            String local = "127.0.0." + (3 + t);
            Thread th = new Thread(() -> {
                byte[] line = ("X-Filler: " + "a".repeat(90) + "\r\n").getBytes(StandardCharsets.US_ASCII);
                for (int c = 0; c < 100_000 && !stop.get(); c++) {
                    try (Socket s = connect(port, local)) {
                        OutputStream out = s.getOutputStream();
                        out.write("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n".getBytes(StandardCharsets.US_ASCII));
                        while (!stop.get() && bytes.get() < (8L << 30)) {
                            out.write(line);
                            bytes.addAndGet(line.length);
                        }
                    } catch (IOException e) {
                        cut.incrementAndGet();
                    }
                }
            }, "attack-headers");
            th.start();
            threads.add(th);
        }
        for (Thread th : threads) th.join(60_000);
        return String.format(Locale.ROOT, "%.1f MB sent, cut %d times", bytes.get() / 1e6, cut.get());
    }

    private static String halfOpen(int port, AtomicBoolean stop, List<Socket> held) throws IOException {
        int opened = 0;
        for (; opened < 500 && !stop.get(); opened++) {
            Socket s = connect(port, "127.0." + (1 + opened / 250) + "." + (1 + opened % 250));
            s.getOutputStream().write("GET / HTTP/1.1\r\n".getBytes(StandardCharsets.US_ASCII));
            held.add(s);
        }
        while (!stop.get()) LockSupport.parkNanos(10_000_000);
        int closed = 0;
        synchronized (held) {
            for (Socket s : held) {
                try {
                    s.setSoTimeout(1);
                    // Whatever the server sent before closing is read first.
                    byte[] buf = new byte[4096];
                    int n = 0;
                    for (int k = 0; k < 1000 && n >= 0; k++) n = s.getInputStream().read(buf);
                    if (n < 0) closed++;
                } catch (IOException e) {
                    if (!(e instanceof java.net.SocketTimeoutException)) closed++;
                }
            }
        }
        return opened + " opened, " + closed + " closed by the server";
    }

    private static byte[] pairJson(String code) {
        return ("{\"type\":\"pair\",\"schema\":1,\"code\":\"" + code + "\"}").getBytes(StandardCharsets.UTF_8);
    }

    /** A client's frame of [opcode], masked with a zero key; payloads under 126 bytes. */
    private static byte[] frame(int opcode, byte[] p) {
        byte[] f = new byte[2 + 4 + p.length];
        f[0] = (byte) (0x80 | opcode);
        f[1] = (byte) (0x80 | p.length);
        System.arraycopy(p, 0, f, 6, p.length);
        return f;
    }

    /** The code of the server's close frame, reading until it comes (bounded by the socket's timeout), or -1. */
    private static int closeCode(Socket s) {
        try {
            java.io.DataInputStream in = new java.io.DataInputStream(s.getInputStream());
            for (int k = 0; k < 10_000; k++) {
                int opcode = in.readUnsignedByte() & 0x0f;
                long len = in.readUnsignedByte() & 0x7f;
                if (len == 126) len = in.readUnsignedShort();
                else if (len == 127) len = in.readLong();
                byte[] payload = new byte[(int) len];
                in.readFully(payload);
                if (opcode == 8) return payload.length >= 2 ? ((payload[0] & 0xff) << 8) | (payload[1] & 0xff) : 1005;
            }
        } catch (IOException ignored) {
        }
        return -1;
    }

    /**
     * Keeps 24 connections open from 127.0.[net].x, each upgraded with [extra] header lines and, when [first] is given,
     * having sent it; reopens those the server closes.
     */
    private static String holdPlaces(int port, AtomicBoolean stop, List<Socket> held, int net, String extra, byte[] first) throws IOException {
        int opened = 0;
        int refused = 0;
        List<Socket> mine = new ArrayList<>();
        while (!stop.get() && opened < 100_000) {
            mine.removeIf(Socket::isClosed);
            // Keep 24 open: reopen those the server closed (a closed one reads as end of stream).
            for (Socket s : new ArrayList<>(mine)) {
                try {
                    s.setSoTimeout(1);
                    // What the server sent before closing (an error, the close frame) is read first.
                    byte[] buf = new byte[4096];
                    int n = 0;
                    for (int k = 0; k < 1000 && n >= 0; k++) n = s.getInputStream().read(buf);
                    if (n < 0) { s.close(); mine.remove(s); }
                } catch (java.net.SocketTimeoutException e) {
                    // still open
                } catch (IOException e) {
                    s.close();
                    mine.remove(s);
                }
            }
            while (mine.size() < 24 && !stop.get()) {
                Socket s = connect(port, "127.0." + net + "." + (1 + opened % 250));
                opened++;
                if (upgrade(s, extra)) {
                    if (first != null) s.getOutputStream().write(first);
                    mine.add(s);
                    held.add(s);
                } else {
                    refused++;
                    s.close();
                }
            }
            LockSupport.parkNanos(50_000_000);
        }
        return opened + " connections opened" + (refused > 0 ? ", " + refused + " upgrades refused" : "");
    }

    private static String preOpened(int port, AtomicBoolean stop, List<Socket> held) throws IOException {
        int tries = 0;
        int wrong = 0;
        int paused = 0;
        for (int round = 0; round < 10_000 && !stop.get(); round++) {
            List<Socket> socks = new ArrayList<>();
            try {
                for (int i = 0; i < 8; i++) {
                    Socket s = connect(port, "127.0.4." + (1 + (round * 8 + i) % 250));
                    socks.add(s);
                    upgrade(s);
                }
                for (int i = 0; i < 8; i++) {
                    socks.get(i).getOutputStream().write(frame(1, pairJson(String.format(Locale.ROOT, "%06d", (round * 8 + i) % 1_000_000))));
                    tries++;
                }
                for (Socket s : socks) {
                    int code = closeCode(s);
                    if (code == 4001) wrong++;
                    else if (code == 4029) paused++;
                }
            } catch (IOException ignored) {
            } finally {
                for (Socket s : socks) s.close();
            }
        }
        return tries + " tries sent: " + wrong + " looked at and wrong, " + paused + " refused unread (pause)";
    }

    private static String guessing(int port, AtomicBoolean stop, List<Socket> held) throws Exception {
        AtomicInteger tries = new AtomicInteger();
        AtomicInteger wrong = new AtomicInteger();
        long t0 = System.nanoTime();
        List<Thread> threads = new ArrayList<>();
        for (int t = 0; t < 4; t++) {
            int id = t;
            Thread th = new Thread(() -> {
                for (int k = 0; k < 1_000_000 && !stop.get(); k++) {
                    try (Socket s = connect(port, "127.0.3." + (1 + (k * 4 + id) % 200))) {
                        if (!upgrade(s)) continue;
                        s.getOutputStream().write(frame(1, pairJson(String.format(Locale.ROOT, "%06d", (k * 4 + id) % 1_000_000))));
                        tries.incrementAndGet();
                        // 4001: looked at and wrong; 4029: refused unread (a pause, or, before, the address locked out).
                        if (closeCode(s) == 4001) wrong.incrementAndGet();
                    } catch (IOException ignored) {
                    }
                }
            }, "attack-guess");
            th.start();
            threads.add(th);
        }
        for (Thread th : threads) th.join(60_000);
        double s = (System.nanoTime() - t0) / 1e9;
        return String.format(Locale.ROOT, "%d tries sent, %.0f a second; %d looked at (%.1f a second)", tries.get(), tries.get() / s, wrong.get(), wrong.get() / s);
    }
}
