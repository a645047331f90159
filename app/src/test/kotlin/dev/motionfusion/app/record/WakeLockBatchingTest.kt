package dev.motionfusion.app.record

import android.content.Intent
import android.hardware.Sensor
import android.hardware.SensorManager
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.app.sensor.WakeLockNeed
import dev.motionfusion.app.offMainThread
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.session.WakeLockUse
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.android.controller.ServiceController
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowPowerManager
import org.robolectric.shadows.ShadowSensorManager

/**
 * A recording holds the CPU only where the sensors cannot wake the phone for their batches themselves
 * (WakeLockNeed, docs/RECORDING.md "Wake lock"): on a phone whose every sensor has a wake-up variant with a
 * FIFO, those are registered with a report latency and the wake lock taken at Record is let go once the
 * recording runs; where one sensor has no wake-up variant, the lock is held to the end. The phones are
 * Robolectric's shadow sensor manager with sensors as SensorBuilder makes them (wake-up flag, FIFO sizes).
 */
@RunWith(RobolectricTestRunner::class)
class WakeLockBatchingTest {
    private val app = RuntimeEnvironment.getApplication()
    private val sensors: ShadowSensorManager = shadowOf(app.getSystemService(SensorManager::class.java))
    private lateinit var graph: TestGraph

    /** Each stream's default sensor (not wake-up) and, except for [withoutWakeUp], its wake-up variant; every one with a FIFO. */
    private fun phone(withoutWakeUp: Set<SessionStream> = emptySet(), wakeUpFifo: Int = 10_000): Map<SessionStream, Sensor> {
        val wakeUp = HashMap<SessionStream, Sensor>()
        for (s in SensorStreams.all) {
            fun sensor(wake: Boolean) = SensorBuilder.newBuilder().setType(s.androidType).setName(if (wake) "BMI260 ${s.name} Wakeup" else "BMI260 ${s.name}")
                .setWakeUpFlag(wake).setFifoMaxEventCount(if (wake) wakeUpFifo else 10_000).setFifoReservedEventCount(if (wake) wakeUpFifo / 4 else 3_000).build()
            sensors.addSensor(sensor(false)) // first: the default one
            if (s !in withoutWakeUp) wakeUp[s] = sensor(true).also(sensors::addSensor)
        }
        graph = TestGraph()
        return wakeUp
    }

    private fun start(): ServiceController<RecordingService> {
        val c = Robolectric.buildService(RecordingService::class.java, Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START))
            .create().startCommand(0, 1)
        graph.settle()
        return c
    }

    /** Stops the recording; returns what its meta.json says of the wake lock. */
    private fun stop(c: ServiceController<RecordingService>): WakeLockUse? {
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        graph.pump()
        graph.settle()
        val dir = (graph.graph.recordings.state.value as RecordingState.Ended).session!!
        return offMainThread { SessionReader.open(dir.toPath()).use { it.metadata.wakeLock } }
    }

    @Test
    fun `wake-up sensors with FIFOs batch on their own - no wake lock while recording, every event recorded`() {
        val wakeUp = phone()
        val c = start()
        val active = graph.graph.recordings.state.value as RecordingState.Active
        val lock = ShadowPowerManager.getLatestWakeLock()
        assertFalse("the lock taken at Record is let go once the recording runs", lock.isHeld)
        assertEquals(WakeLockNeed.HARDWARE_BATCHING, graph.capture.wakeLockNeed)
        // The wake-up variants are registered, with a report latency (batched in hardware).
        val listener = sensors.listeners.single()
        for ((stream, s) in wakeUp) assertTrue("$stream: its wake-up sensor", sensors.hasListener(listener, s))
        assertTrue("batched: ${graph.capture.reportLatencyUs} µs", graph.capture.reportLatencyUs > 0)
        // The names shown (and the calibration's device key) stay the default sensors'.
        assertEquals("BMI260 ACCELEROMETER", graph.capture.sensorInfo.getValue(SensorKind.ACCELEROMETER).name)
        // A batch delivered by the wake-up accelerometer is recorded.
        for (i in 0 until 200) {
            sensors.sendSensorEventToListeners(
                SensorEventBuilder.newBuilder().setSensor(wakeUp.getValue(SessionStream.ACCELEROMETER)).setValues(floatArrayOf(0f, 0f, 9.81f))
                    .setTimestamp(1_000_000_000L + i * 5_000_000L).setAccuracy(SensorManager.SENSOR_STATUS_ACCURACY_HIGH).build(),
            )
        }
        repeat(8) { graph.pump() } // past the reorder window, as wide as a batch
        assertEquals(200L, active.rows())
        // A minute of ticks later the lock is still not taken again (no renewal of a lock not needed).
        graph.clock.elapsedNs += 61_000_000_000L
        shadowOf(android.os.Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(61))
        assertFalse(ShadowPowerManager.getLatestWakeLock().isHeld)
        assertEquals("meta.json: let go, nothing forced it", WakeLockUse(false, "hardware_batching", emptyList()), stop(c))
    }

    @Test
    fun `one sensor without a wake-up variant - the lock is held for the whole recording`() {
        phone(withoutWakeUp = setOf(SessionStream.MAGNETOMETER))
        val c = start()
        assertTrue(graph.graph.recordings.state.value is RecordingState.Active)
        assertEquals(WakeLockNeed.NOT_WAKE_UP, graph.capture.wakeLockNeed)
        val lock = ShadowPowerManager.getLatestWakeLock()
        assertTrue(lock.isHeld)
        graph.clock.elapsedNs += 61_000_000_000L
        shadowOf(android.os.Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(61))
        assertTrue("renewed, still held", ShadowPowerManager.getLatestWakeLock().isHeld)
        assertEquals("meta.json: held, forced by the magnetometer", WakeLockUse(true, "not_wake_up", listOf(SessionStream.MAGNETOMETER)), stop(c))
        assertFalse(ShadowPowerManager.getLatestWakeLock().isHeld)
    }

    @Test
    fun `wake-up sensors whose FIFOs hold too little to batch - the lock is held`() {
        phone(wakeUpFifo = 4) // a few events: no report latency worth batching
        val c = start()
        assertTrue(graph.graph.recordings.state.value is RecordingState.Active)
        assertEquals(0, graph.capture.reportLatencyUs)
        assertEquals(WakeLockNeed.FIFO_TOO_SMALL, graph.capture.wakeLockNeed)
        assertTrue(ShadowPowerManager.getLatestWakeLock().isHeld)
        assertEquals("meta.json: held, every stream's FIFO together too small", WakeLockUse(true, "fifo_too_small", SensorStreams.all.sortedBy { it.ordinal }), stop(c))
        assertFalse(ShadowPowerManager.getLatestWakeLock().isHeld)
    }
}
