package dev.motionfusion.app

import android.content.Intent
import android.content.res.Configuration
import android.hardware.Sensor
import android.hardware.SensorEventListener
import android.hardware.SensorManager
import android.os.Looper
import dev.motionfusion.app.record.LineFormat
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.event.SessionStream
import org.junit.Assert.assertEquals
import org.junit.Assert.assertNotSame
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowSensorManager

/**
 * The live screen turned (or its theme, font size or window size changed) while it shows the capture,
 * with and without a recording: the activity is recreated, the capture is not let go — no sensor
 * listener unregistered, no event lost, the filter and the recording going on without a gap.
 */
@RunWith(RobolectricTestRunner::class)
class ConfigurationChangeTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var sensors: ShadowSensorManager
    private lateinit var all: Map<SessionStream, Sensor>
    private val format = LineFormat()
    private lateinit var graph: TestGraph
    private var t = 1_000_000_000L

    @Before
    fun setUp() {
        sensors = shadowOf(app.getSystemService(SensorManager::class.java))
        // Sensors with a FIFO: a recording batches, and a screen on top adds a listener that asks for every event at once.
        all = SensorStreams.all.associateWith { s ->
            SensorBuilder.newBuilder().setType(s.androidType).setName("Test ${s.name}").setMinDelay(2_500)
                .setFifoMaxEventCount(3000).setFifoReservedEventCount(0).build().also(sensors::addSensor)
        }
        graph = TestGraph(format = format)
        graph.graph.setNotificationsAnswered()
        // What the sensor manager holds as each activity's onStop and onDestroy end (their super calls tell these callbacks).
        app.registerActivityLifecycleCallbacks(object : android.app.Application.ActivityLifecycleCallbacks {
            override fun onActivityStopped(activity: android.app.Activity) {
                seen += "stopped" to sensors.listeners.toSet()
            }

            override fun onActivityDestroyed(activity: android.app.Activity) {
                seen += "destroyed" to sensors.listeners.toSet()
            }

            override fun onActivityCreated(activity: android.app.Activity, savedInstanceState: android.os.Bundle?) = Unit
            override fun onActivityStarted(activity: android.app.Activity) = Unit
            override fun onActivityResumed(activity: android.app.Activity) = Unit
            override fun onActivityPaused(activity: android.app.Activity) = Unit
            override fun onActivitySaveInstanceState(activity: android.app.Activity, outState: android.os.Bundle) = Unit
        })
    }

    /** The sensor listeners registered when an activity had stopped or was destroyed, in order. */
    private val seen = ArrayList<Pair<String, Set<SensorEventListener>>>()

    /** One 200 Hz round of every stream. */
    private fun sendRound() {
        SensorStreams.all.forEachIndexed { i, s ->
            val values = FloatArray(s.valueCount) { if (s == SessionStream.ACCELEROMETER && it == 2) 9.81f else 0.1f }
            sensors.sendSensorEventToListeners(
                SensorEventBuilder.newBuilder().setSensor(all.getValue(s)).setValues(values).setTimestamp(t + i)
                    .setAccuracy(SensorManager.SENSOR_STATUS_ACCURACY_HIGH).build(),
            )
        }
        t += 5_000_000L
    }

    private fun rounds(n: Int) {
        repeat(n) { sendRound() }
        graph.pump()
    }

    private fun landscape() = Configuration(app.resources.configuration).apply { orientation = Configuration.ORIENTATION_LANDSCAPE }

    @Test
    fun `a rotation mid-recording unregisters no sensor and leaves no gap in the recording or the filter`() {
        val main = Robolectric.buildActivity(MainActivity::class.java).setup()
        val c = Robolectric.buildService(RecordingService::class.java, Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START))
            .create().startCommand(0, 1)
        graph.settle()
        val active = graph.graph.recordings.state.value as? RecordingState.Active ?: error("not recording: ${graph.graph.recordings.state.value}")
        rounds(100)
        val listeners = sensors.listeners.toSet()
        assertEquals("the recording's listener and the screen's", 2, listeners.size)
        val steps = graph.capture.state.value.filterSteps
        assertTrue(steps > 0)
        val before = main.get()

        seen.clear()
        main.configurationChange(landscape())
        shadowOf(Looper.getMainLooper()).idle()
        assertNotSame("recreated with the landscape layout", before, main.get())
        // Through the old activity's stop and destruction, every listener stayed registered: none was unregistered.
        assertEquals(listOf("stopped" to listeners, "destroyed" to listeners), seen)
        assertEquals(listeners, sensors.listeners.toSet())

        rounds(100)
        // Every event of both sides of the rotation recorded, 5 ms apart on each stream: no gap.
        assertEquals(200L * SensorStreams.all.size, active.rows())
        val gyro = offMainThread { LineFormat.rows(active.session) }.filter { it.startsWith("GYROSCOPE,") }.map { it.split(',')[1].toLong() }
        assertEquals(200, gyro.size)
        assertEquals(setOf(5_000_000L), gyro.zipWithNext { a, b -> b - a }.toSet())
        // The same filter went on stepping through the turn: one step a gyroscope sample.
        assertEquals(steps + 100, graph.capture.state.value.filterSteps)

        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        graph.pump()
        graph.settle()
        // Leaving the screen (not a configuration change) lets the capture go.
        main.pause().stop().destroy()
        graph.settle()
        assertTrue("unregistered once nothing holds the capture", sensors.listeners.isEmpty())
    }

    @Test
    fun `a rotation with nothing recording keeps the capture running, no unregister, the filter going on`() {
        val main = Robolectric.buildActivity(MainActivity::class.java).setup()
        rounds(50)
        val steps = graph.capture.state.value.filterSteps
        val listeners = sensors.listeners.toSet()
        assertTrue(listeners.isNotEmpty())
        seen.clear()
        main.recreate()
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals(listOf("stopped" to listeners, "destroyed" to listeners), seen)
        assertTrue(graph.capture.isRunning)
        rounds(50)
        assertEquals(steps + 50, graph.capture.state.value.filterSteps)
        main.pause().stop().destroy()
        graph.settle()
        assertTrue(sensors.listeners.isEmpty())
    }
}
