package dev.motionfusion.app.stream

import android.hardware.Sensor
import android.hardware.SensorManager
import android.widget.CompoundButton
import android.widget.TextView
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.TestGraph
import java.net.InetSocketAddress
import java.net.ServerSocket
import org.junit.After
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.Config
import org.robolectric.annotation.GraphicsMode
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.ShadowLog

/**
 * A stream that cannot start is told in the user's language, saying what failed and what to do; the
 * system's words (English) go to the log only. Rendered to target/screenshots/de-stream-port-taken.png.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
@Config(qualifiers = "de-rDE-w400dp-h860dp-port-notnight-xhdpi")
class StreamFailureTextTest {
    private lateinit var graph: TestGraph

    @After
    fun tearDown() {
        graph.graph.stream.stop()
        graph.settle()
    }

    @Test
    fun `a port another app holds is told in German, with what to do, the system's words in the log`() {
        val app = RuntimeEnvironment.getApplication()
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        for (type in listOf(Sensor.TYPE_ACCELEROMETER, Sensor.TYPE_GYROSCOPE)) sm.addSensor(SensorBuilder.newBuilder().setType(type).build())
        shadowOf(app).grantPermissions(android.Manifest.permission.POST_NOTIFICATIONS)
        ServerSocket().use { taken ->
            taken.reuseAddress = false
            taken.bind(InetSocketAddress("0.0.0.0", 0))
            graph = TestGraph(streamPort = taken.localPort)
            val a = Robolectric.buildActivity(StreamActivity::class.java).setup().get()
            a.findViewById<CompoundButton>(R.id.stream_switch).performClick()
            graph.settle()
            assertEquals(StreamState.Failed(R.string.stream_failure_port_in_use), graph.graph.stream.state.value)
            val shown = a.findViewById<TextView>(R.id.stream_message).text.toString()
            assertEquals(
                "Streamen ist aus: eine andere App auf diesem Telefon belegt den Port des Streams: diese App schließen, dann das Streamen wieder einschalten",
                shown,
            )
            assertFalse(shown, shown.contains("${taken.localPort}"))
            val logged = ShadowLog.getLogsForTag("StreamController")
            assertTrue("the exception in the log: $logged", logged.any { it.throwable?.message?.contains("${taken.localPort}") == true })
            Screenshots.captureScreen(a, "de-stream-port-taken")
        }
    }
}
