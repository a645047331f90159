package dev.motionfusion.app.record

import android.content.Intent
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.event.SessionStream
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.ShadowSensorManager

/**
 * A recording on a device whose sensors report a FIFO: registered with the report latency chosen
 * from it while nothing is on screen, every event at once again while a screen holds the capture,
 * and meta.json names the latency the recording's listener was registered with.
 */
@RunWith(RobolectricTestRunner::class)
class BatchedRecordingTest {
    private val app = RuntimeEnvironment.getApplication()
    private val sensors: ShadowSensorManager = shadowOf(app.getSystemService(SensorManager::class.java))

    /** Every stream's sensor with [fifoMax] events of FIFO, shared (none reserved), at most 400 Hz. */
    private fun device(fifoMax: Int): Map<SessionStream, Sensor> = SensorStreams.all.associateWith { s ->
        SensorBuilder.newBuilder().setType(s.androidType).setName("Test ${s.name}").setMinDelay(2_500)
            .setFifoMaxEventCount(fifoMax).setFifoReservedEventCount(0).build().also(sensors::addSensor)
    }

    private fun record(graph: TestGraph, during: () -> Unit) {
        val c = Robolectric.buildService(RecordingService::class.java, Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START))
            .create().startCommand(0, 1)
        graph.settle()
        assertTrue(graph.graph.recordings.isRecording)
        during()
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        graph.pump()
        graph.settle()
        assertTrue(graph.graph.recordings.state.value is RecordingState.Ended)
        assertTrue(sensors.listeners.isEmpty())
    }

    @Test
    fun `with a FIFO the recording batches while nothing is on screen, and meta_json names the latency`() {
        device(fifoMax = 3000)
        val format = LineFormat()
        val graph = TestGraph(format = format)
        // The default 100 Hz, 8 streams: 800 events/s; half of 3000 lasts 1.875 s.
        val expected = 1_875_000
        record(graph) {
            val capture = graph.capture
            assertEquals(expected, capture.reportLatencyUs)
            assertEquals("only the recording's listener", 1, sensors.listeners.size)
            assertEquals(SensorStreams.all.size, format.metadata!!.sensors.size)
            format.metadata!!.sensors.forEach { assertEquals(it.stream.key, expected, it.maxReportLatencyUs) }

            // The live screen comes: a second listener asks for every event at once; the recording's stays as it was.
            val recording = sensors.listeners.single()
            capture.acquire(onScreen = true)
            assertEquals(2, sensors.listeners.size)
            assertTrue(recording in sensors.listeners)
            SensorStreams.all.forEach { s -> assertTrue(sensors.listeners.all { l -> sensors.hasListener(l, graph.capture.sensors.getValue(s)) }) }
            shadowOf(Looper.getMainLooper()).idle() // the flush asked for completes
            capture.release(onScreen = true)
            assertEquals(listOf(recording), sensors.listeners)
            assertEquals(expected, capture.reportLatencyUs)
        }
    }

    @Test
    fun `without a FIFO nothing is batched and meta_json says 0`() {
        device(fifoMax = 0)
        val format = LineFormat()
        val graph = TestGraph(format = format)
        record(graph) {
            assertEquals(0, graph.capture.reportLatencyUs)
            format.metadata!!.sensors.forEach { assertEquals(0, it.maxReportLatencyUs) }
            graph.capture.acquire(onScreen = true)
            assertEquals("no second listener: the events come at once anyway", 1, sensors.listeners.size)
            graph.capture.release(onScreen = true)
        }
    }
}
