package dev.motionfusion.app.stream

import android.content.ClipboardManager
import android.graphics.Bitmap
import android.graphics.Canvas
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.view.View
import android.widget.CompoundButton
import android.widget.TextView
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.TestGraph
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.stream.StreamMessage
import com.google.zxing.BinaryBitmap
import com.google.zxing.RGBLuminanceSource
import com.google.zxing.common.HybridBinarizer
import com.google.zxing.qrcode.QRCodeReader
import dev.motionfusion.stream.StreamClient
import java.net.DatagramPacket
import java.net.DatagramSocket
import java.net.InetAddress
import java.net.InetSocketAddress
import java.net.URI
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicBoolean
import dev.motionfusion.stream.StreamServerSettings
import org.junit.After
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.Config
import org.robolectric.annotation.GraphicsMode
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.ShadowToast

/**
 * The Stream screen rendered to PNG (target/screenshots) off, starting, on and waiting for a client,
 * with a paired client getting samples (a real [StreamClient] on loopback), and with a client that
 * stopped reading shown as stalled, with the layout and accessibility checks of every screenshot.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
@Config(qualifiers = "w400dp-h860dp-port-notnight-xhdpi")
class StreamScreensTest {
    private lateinit var graph: TestGraph
    private var client: StreamClient? = null
    /** Holds a stalled client's reading thread until the test ends. */
    private val unstall = CountDownLatch(1)

    @Before
    fun setUp() {
        val sm = shadowOf(RuntimeEnvironment.getApplication().getSystemService(SensorManager::class.java))
        for (type in listOf(Sensor.TYPE_ACCELEROMETER, Sensor.TYPE_GYROSCOPE, Sensor.TYPE_MAGNETIC_FIELD)) {
            sm.addSensor(SensorBuilder.newBuilder().setType(type).build())
        }
        graph = TestGraph(streamPort = StreamController.PORT)
        // Notifications allowed (StreamNotificationsTest covers the question on API 33+): the switch starts at once.
        shadowOf(RuntimeEnvironment.getApplication()).grantPermissions(android.Manifest.permission.POST_NOTIFICATIONS)
    }

    private val pool = java.util.concurrent.Executors.newSingleThreadExecutor()

    /** Connects [c] on a thread of its own (it waits for the user's answer on the phone); the hello, or what failed. */
    private fun connectInBackground(c: StreamClient) = pool.submit<StreamMessage.Hello> { c.connect() }

    /** Runs the main thread until the screen's state shows a laptop asking to connect (bounded). */
    private fun awaitAsking(): dev.motionfusion.stream.StreamClientInfo {
        repeat(10_000) {
            shadowOf(Looper.getMainLooper()).idle()
            (graph.graph.stream.state.value as? StreamState.On)?.clients?.firstOrNull { it.awaitingConfirmation }?.let { return it }
            java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
        }
        error("nobody asks: ${graph.graph.stream.state.value}")
    }

    /** Pairs [c] as a user would: it asks, Allow on the screen. */
    private fun pairAllowed(a: StreamActivity, c: StreamClient) {
        val hello = connectInBackground(c)
        awaitAsking()
        a.findViewById<View>(R.id.stream_request_allow).performClick()
        graph.settle()
        hello.get(10, TimeUnit.SECONDS)
        shadowOf(Looper.getMainLooper()).idle()
    }

    /** The text of the QR code [v] draws, read by ZXing's reader from the view's pixels as the screen shows them. */
    private fun decodeQr(v: View): String {
        val b = Bitmap.createBitmap(v.width, v.height, Bitmap.Config.ARGB_8888)
        v.draw(Canvas(b))
        val pixels = IntArray(b.width * b.height).also { b.getPixels(it, 0, b.width, 0, 0, b.width, b.height) }
        val image = BinaryBitmap(HybridBinarizer(RGBLuminanceSource(b.width, b.height, pixels)))
        return QRCodeReader().decode(image).text
    }

    @After
    fun tearDown() {
        pool.shutdownNow()
        unstall.countDown()
        client?.close()
        graph.graph.stream.stop()
        // The server closes on the control executor: run it, so that the port is free for the next test.
        graph.settle()
    }

    @Test
    fun `off, on and waiting, and a paired client with its rate and drops`() {
        val a = Robolectric.buildActivity(StreamActivity::class.java).setup().get()
        val switch = a.findViewById<CompoundButton>(R.id.stream_switch)
        assertFalse("off by default", switch.isChecked)
        assertEquals(View.GONE, a.findViewById<View>(R.id.stream_details).visibility)
        Screenshots.captureScreen(a, "stream-off")

        switch.performClick()
        // The server starts off the main thread: meanwhile the switch waits and the screen says so.
        assertEquals(StreamState.Starting, graph.graph.stream.state.value)
        assertTrue(switch.isChecked)
        assertFalse(switch.isEnabled)
        assertEquals("Starting the server…", a.findViewById<TextView>(R.id.stream_message).text.toString())
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofMillis(500)) // the switch's thumb moves
        Screenshots.captureScreen(a, "stream-starting")
        graph.settle()
        val on = graph.graph.stream.state.value as StreamState.On
        assertTrue(switch.isChecked)
        assertTrue(switch.isEnabled)
        assertEquals(View.GONE, a.findViewById<View>(R.id.stream_message).visibility)
        assertTrue(graph.capture.isRunning)
        assertEquals(on.code, a.findViewById<TextView>(R.id.stream_code).text.toString())
        assertEquals("ws://192.168.1.23:8765", a.findViewById<TextView>(R.id.stream_addresses).text.toString())
        assertEquals("adb forward tcp:8765 tcp:8765, then ws://127.0.0.1:8765", a.findViewById<TextView>(R.id.stream_usb).text.toString())
        Screenshots.captureScreen(a, "stream-waiting")
        // The laptop's command: as text, as a QR code a reader decodes from the view as drawn, and copied.
        val command = "fusion listen ws://192.168.1.23:8765 --code ${on.code}"
        assertEquals(command, a.findViewById<TextView>(R.id.stream_command).text.toString())
        assertEquals(command, decodeQr(a.findViewById(R.id.stream_qr)))
        a.findViewById<View>(R.id.stream_copy).performClick()
        val clip = a.getSystemService(ClipboardManager::class.java).primaryClip!!
        assertEquals(command, clip.getItemAt(0).text.toString())
        assertTrue("marked sensitive", clip.description.extras!!.getBoolean("android.content.extra.IS_SENSITIVE"))

        val got = CountDownLatch(400)
        client = StreamClient(URI("ws://127.0.0.1:8765"), StreamMessage.Pair(on.code, client = "fusion listen on lab-laptop")) {
            if (it is StreamMessage.Sample) got.countDown()
        }
        // The right code: the laptop asks, with its name and address, and waits for Allow.
        val hello = connectInBackground(client!!)
        awaitAsking()
        assertEquals(View.VISIBLE, a.findViewById<View>(R.id.stream_request).visibility)
        assertEquals(
            "“fusion listen on lab-laptop” at 127.0.0.1. Allow it only if it is yours: it will get everything this phone streams.",
            a.findViewById<TextView>(R.id.stream_request_text).text.toString(),
        )
        assertEquals("127.0.0.1: asks to connect, waiting for your answer", a.findViewById<TextView>(R.id.stream_clients).text.toString())
        assertFalse(hello.isDone)
        Screenshots.captureScreen(a, "stream-request")
        a.findViewById<View>(R.id.stream_request_allow).performClick()
        graph.settle()
        hello.get(10, TimeUnit.SECONDS)
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals(View.GONE, a.findViewById<View>(R.id.stream_request).visibility)
        val v = floatArrayOf(0.01f, -0.02f, 0.003f)
        for (i in 0 until 400) graph.capture.ring.offer(SessionStream.GYROSCOPE, 1_000_000_000L + i * 5_000_000L, 3, v, 3)
        graph.pump()
        assertTrue("the client got the samples", got.await(10, TimeUnit.SECONDS))
        // The sender counted them before they left; the screen shows them at its next refresh.
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        val c = (graph.graph.stream.state.value as StreamState.On).clients.single()
        assertTrue("$c", c.sent >= 400 && c.achievedRateHz > 0)
        assertTrue(a.findViewById<TextView>(R.id.stream_clients).text.contains("${c.sent} sent"))
        val line = a.findViewById<TextView>(R.id.stream_clients).text.toString()
        assertTrue(line, line.startsWith("127.0.0.1: ") && line.endsWith("0 dropped") && "stalled" !in line)
        Screenshots.captureScreen(a, "stream-client")

        // The UDP push: a target that is not host:port, then a receiver on loopback.
        val target = a.findViewById<android.widget.EditText>(R.id.stream_udp_target)
        val push = a.findViewById<TextView>(R.id.stream_udp_button)
        target.setText("laptop")
        push.performClick()
        assertEquals("Enter host:port, for example 192.168.1.20:9000.", a.findViewById<TextView>(R.id.stream_udp_status).text.toString())
        DatagramSocket(InetSocketAddress(InetAddress.getLoopbackAddress(), 0)).use { receiver ->
            receiver.soTimeout = 10_000
            target.setText("127.0.0.1:${receiver.localPort}")
            push.performClick()
            assertEquals("Looking up 127.0.0.1:${receiver.localPort}…", a.findViewById<TextView>(R.id.stream_udp_status).text.toString())
            graph.settle()
            assertEquals("Stop UDP", push.text.toString())
            for (i in 0 until 100) graph.capture.ring.offer(SessionStream.GYROSCOPE, 4_000_000_000L + i * 5_000_000L, 3, v, 3)
            graph.pump()
            var samples = 0
            val buf = ByteArray(65_536)
            while (samples < 100) {
                val p = DatagramPacket(buf, buf.size)
                receiver.receive(p)
                if (String(buf, 0, p.length, Charsets.UTF_8).startsWith("{\"type\":\"sample\"")) samples++
            }
            shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1)) // the screen's refresh
            val udp = (graph.graph.stream.state.value as StreamState.On).udp as UdpView.Pushing
            // The receiver may see the last datagram before the sender has counted it.
            assertTrue("$udp", udp.sent >= 99)
            assertEquals(
                "Pushing to 127.0.0.1:${receiver.localPort}: ${udp.sent} sent, 0 dropped",
                a.findViewById<TextView>(R.id.stream_udp_status).text.toString(),
            )
            Screenshots.captureScreen(a, "stream-udp")
            // The target is kept (SettingsRepositoryTest: across a restart too): the screen opened again offers it.
            graph.settle()
            val b = Robolectric.buildActivity(StreamActivity::class.java).setup()
            graph.settle()
            assertEquals("127.0.0.1:${receiver.localPort}", b.get().findViewById<android.widget.EditText>(R.id.stream_udp_target).text.toString())
            b.pause().stop().destroy()
        }

        switch.performClick()
        assertEquals(StreamState.Stopping, graph.graph.stream.state.value)
        assertFalse(switch.isChecked)
        assertFalse(switch.isEnabled)
        assertEquals("Closing the connections…", a.findViewById<TextView>(R.id.stream_message).text.toString())
        graph.settle()
        assertTrue(switch.isEnabled)
        assertEquals(StreamState.Off, graph.graph.stream.state.value)
        assertTrue(client!!.awaitClose(5_000))
        assertEquals(View.GONE, a.findViewById<View>(R.id.stream_details).visibility)
    }

    @Test
    @Config(minSdk = 32, maxSdk = 33)
    fun `the command copied, confirmed by a toast before Android 13, by the system from 13 on`() {
        val a = Robolectric.buildActivity(StreamActivity::class.java).setup().get()
        a.findViewById<CompoundButton>(R.id.stream_switch).performClick()
        graph.settle()
        val on = graph.graph.stream.state.value as StreamState.On
        a.findViewById<View>(R.id.stream_copy).performClick()
        assertEquals(
            "fusion listen ws://192.168.1.23:8765 --code ${on.code}",
            a.getSystemService(ClipboardManager::class.java).primaryClip!!.getItemAt(0).text.toString(),
        )
        assertEquals(if (android.os.Build.VERSION.SDK_INT < 33) "Command copied" else null, ShadowToast.getTextOfLatestToast())
    }

    @Test
    fun `a client that stopped reading is shown as stalled`() {
        // A small queue per client, so that the sockets' buffers fill sooner.
        graph = TestGraph(streamPort = StreamController.PORT, streamSettings = StreamServerSettings(clientQueueFrames = 16))
        val a = Robolectric.buildActivity(StreamActivity::class.java).setup().get()
        a.findViewById<CompoundButton>(R.id.stream_switch).performClick()
        graph.settle()
        val on = graph.graph.stream.state.value as StreamState.On
        val stalled = AtomicBoolean(false)
        client = StreamClient(URI("ws://127.0.0.1:${on.port}"), StreamMessage.Pair(on.code)) { if (stalled.get()) unstall.await() }
        pairAllowed(a, client!!)
        stalled.set(true)
        val v = floatArrayOf(0.01f, -0.02f, 0.003f)
        var t = 1_000_000_000L
        var rounds = 0
        while (true) {
            // Five seconds of gyroscope samples a round, until the sockets' buffers are full and the phone drops.
            check(rounds++ < 400) { "the client was never shown as stalled: ${graph.graph.stream.state.value}" }
            for (i in 0 until 1000) {
                graph.capture.ring.offer(SessionStream.GYROSCOPE, t, 3, v, 3)
                t += 5_000_000L
            }
            graph.pump()
            // The screen's refresh.
            shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
            val c = (graph.graph.stream.state.value as StreamState.On).clients.single()
            if (c.stalled) break
        }
        val c = (graph.graph.stream.state.value as StreamState.On).clients.single()
        assertTrue("$c", c.dropped > 0)
        assertEquals(
            "127.0.0.1: stalled, not keeping up; ${c.sent} sent, ${c.dropped} dropped",
            a.findViewById<TextView>(R.id.stream_clients).text.toString(),
        )
        Screenshots.captureScreen(a, "stream-stalled")
    }

    @Test
    @Config(qualifiers = "de-w400dp-h860dp-port-night-xhdpi")
    fun `German and dark, on and waiting, then a laptop without a name asks and is denied`() {
        val a = Robolectric.buildActivity(StreamActivity::class.java).setup().get()
        a.findViewById<CompoundButton>(R.id.stream_switch).performClick()
        graph.settle()
        assertEquals("Warte auf einen Client …", a.findViewById<TextView>(R.id.stream_clients).text.toString())
        Screenshots.captureScreen(a, "stream-waiting-de-dark")
        val code = (graph.graph.stream.state.value as StreamState.On).code
        client = StreamClient(URI("ws://127.0.0.1:8765"), StreamMessage.Pair(code)) {}
        val hello = connectInBackground(client!!)
        awaitAsking()
        assertEquals(
            "Ein Client ohne Namen unter 127.0.0.1. Nur erlauben, wenn es Ihr Gerät ist: Es erhält alles, was dieses Telefon sendet.",
            a.findViewById<TextView>(R.id.stream_request_text).text.toString(),
        )
        Screenshots.captureScreen(a, "stream-request-de-dark")
        a.findViewById<View>(R.id.stream_request_deny).performClick()
        graph.settle()
        val e = runCatching { hello.get(10, TimeUnit.SECONDS) }.exceptionOrNull()
        assertTrue("$e", e?.cause?.message?.contains("denied on the phone") == true)
        // Whoever asked knew the code: a new one is shown.
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals(View.GONE, a.findViewById<View>(R.id.stream_request).visibility)
        val newCode = a.findViewById<TextView>(R.id.stream_code).text.toString()
        assertFalse(code == newCode)
        // The command and its QR code follow the new code.
        assertEquals("fusion listen ws://192.168.1.23:8765 --code $newCode", decodeQr(a.findViewById(R.id.stream_qr)))
    }

    @Test
    fun `remote control allowed, and a laptop in control`() {
        val a = Robolectric.buildActivity(StreamActivity::class.java).setup().get()
        val remote = a.findViewById<CompoundButton>(R.id.stream_remote_switch)
        assertFalse("remote control off by default", remote.isChecked)
        a.findViewById<CompoundButton>(R.id.stream_switch).performClick()
        graph.settle()
        remote.performClick()
        assertTrue(graph.graph.stream.remoteControlAllowed)
        val on = graph.graph.stream.state.value as StreamState.On
        val answers = java.util.concurrent.LinkedBlockingQueue<StreamMessage>()
        val c = StreamClient(URI("ws://127.0.0.1:${on.port}"), StreamMessage.Pair(on.code, emptyList(), client = "fusion record on lab-laptop")) { answers += it }
        client = c
        pairAllowed(a, c)
        assertTrue(c.send(StreamMessage.Control(1, StreamMessage.Control.Command.STOP, 1)))
        // The answer (nothing is recording here), then the screen names the laptop in control.
        val answer = answers.poll(10, TimeUnit.SECONDS) as StreamMessage.ControlResult
        assertEquals("not recording", answer.reason)
        repeat(10_000) {
            shadowOf(Looper.getMainLooper()).idle()
            if ((graph.graph.stream.state.value as? StreamState.On)?.controlledBy != null) return@repeat
            java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
        }
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofMillis(500))
        val by = a.findViewById<TextView>(R.id.stream_controlled_by)
        assertEquals(View.VISIBLE, by.visibility)
        assertEquals("Controlled by fusion record on lab-laptop (127.0.0.1)", by.text.toString())
        Screenshots.captureScreen(a, "stream-remote-control")
        // Off again: nobody in control.
        remote.performClick()
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals(View.GONE, by.visibility)
    }
}
