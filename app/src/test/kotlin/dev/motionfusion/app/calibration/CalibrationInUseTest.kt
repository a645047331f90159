package dev.motionfusion.app.calibration

import android.content.Intent
import android.hardware.Sensor
import android.hardware.SensorManager
import android.view.View
import android.widget.TextView
import dev.motionfusion.app.MainActivity
import dev.motionfusion.app.R
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.CalibratedEvents
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.EllipsoidModel
import dev.motionfusion.core.calib.GyroscopeCalibration
import dev.motionfusion.core.calib.MagnetometerCalibration
import dev.motionfusion.core.calib.Matrix3
import dev.motionfusion.core.calib.SensorCorrection
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.session.SessionCalibration
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.launch
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNull
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.android.controller.ServiceController
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowSensorManager
import java.io.File
import kotlin.math.abs
import kotlin.math.asin
import kotlin.math.sqrt

/**
 * The stored calibration in use on the phone, with the sensors of ShadowSensorManager and the
 * real session format: applied in the live filter when the user chooses (the corrected
 * uncalibrated streams in place of Android's calibrated ones), written into meta.json, replayed
 * by core to the same orientation; the calibration screen on the one capture; the still recording.
 */
@RunWith(RobolectricTestRunner::class)
class CalibrationInUseTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var sensors: ShadowSensorManager
    private lateinit var all: Map<SessionStream, Sensor>
    private lateinit var graph: TestGraph

    /** The phone's errors: what the uncalibrated streams carry, and Android's own (poorer) estimates of them. */
    private val hardIron = Vector3(35.0, -20.0, 60.0)
    private val androidHardIron = Vector3(38.0, -22.0, 61.0)
    private val gyroBias = Vector3(0.02, -0.01, 0.015)
    private val androidGyroBias = Vector3(0.01, -0.005, 0.0075)

    private val calibration = Calibration(
        magnetometer = MagnetometerCalibration(
            SensorCorrection(hardIron, Matrix3.IDENTITY), SessionStream.MAGNETOMETER_UNCALIBRATED, EllipsoidModel.SPHERE, 50.0, 0.3, 0.8, 5000, 10.0, 0.3,
        ),
        gyroscope = GyroscopeCalibration(gyroBias, SessionStream.GYROSCOPE_UNCALIBRATED, 30.0, 10, Vector3(1e-5, 1e-5, 1e-5), Vector3(0.003, 0.003, 0.003)),
        source = "test",
    )

    @Before
    fun setUp() {
        sensors = shadowOf(app.getSystemService(SensorManager::class.java))
        all = SensorStreams.all.associateWith { s ->
            SensorBuilder.newBuilder().setType(s.androidType).setName("Test ${s.name}").build().also(sensors::addSensor)
        }
        graph = TestGraph()
        graph.settle() // the store reads its file
    }

    private fun store(c: Calibration, useLive: Boolean) {
        val store = graph.graph.calibrationStore
        var stored = false
        CoroutineScope(Dispatchers.Main.immediate).launch { store.accept(c); stored = true }
        graph.settle()
        assertTrue(stored)
        store.setUseInLiveFilter(useLive)
    }

    private fun send(stream: SessionStream, t: Long, v: FloatArray) {
        sensors.sendSensorEventToListeners(
            SensorEventBuilder.newBuilder().setSensor(all.getValue(stream)).setValues(v).setTimestamp(t)
                .setAccuracy(SensorManager.SENSOR_STATUS_ACCURACY_HIGH).build(),
        )
    }

    private fun f(a: Vector3, b: Vector3? = null) =
        if (b == null) floatArrayOf(a.x.toFloat(), a.y.toFloat(), a.z.toFloat()) else floatArrayOf(a.x.toFloat(), a.y.toFloat(), a.z.toFloat(), b.x.toFloat(), b.y.toFloat(), b.z.toFloat())

    /** A simulated motion as the phone delivers it: uncalibrated streams with the errors, calibrated ones with Android's estimates removed. */
    private fun deliverMotion(seconds: Double): Vector3 {
        var lastTrueField = Vector3(0.0, 0.0, 0.0)
        var i = 0
        MotionSimulator(SimulationSettings(seed = 3, rateHz = 100.0, durationS = seconds)).forEach { s ->
            val t = 1_000_000_000L + s.timestampNs
            val magRaw = s.mag + hardIron
            val gyroRaw = s.gyro + gyroBias
            send(SessionStream.ACCELEROMETER, t, f(s.acc))
            send(SessionStream.MAGNETOMETER_UNCALIBRATED, t + 100_000, f(magRaw, androidHardIron))
            send(SessionStream.MAGNETOMETER, t + 150_000, f(magRaw - androidHardIron))
            send(SessionStream.GYROSCOPE_UNCALIBRATED, t + 200_000, f(gyroRaw, androidGyroBias))
            send(SessionStream.GYROSCOPE, t + 250_000, f(gyroRaw - androidGyroBias))
            lastTrueField = s.mag
            if (++i % 100 == 0) graph.capture.pump()
        }
        graph.pump()
        return lastTrueField
    }

    private fun startService(still: Boolean = false): ServiceController<RecordingService> {
        val intent = Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START).putExtra(RecordingService.EXTRA_STILL, still)
        val c = Robolectric.buildService(RecordingService::class.java, intent).create().startCommand(0, 1)
        graph.settle()
        return c
    }

    private fun stop(c: ServiceController<RecordingService>): File {
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        graph.pump()
        graph.settle()
        val ended = graph.graph.recordings.state.value as RecordingState.Ended
        return ended.session!!
    }

    /** Orientations of `fusion replay`'s engine on [events]. */
    private fun replay(reader: SessionReader, events: SensorEvents, settings: FilterSettings = reader.metadata.filterSettings!!): List<DoubleArray> {
        val out = ArrayList<DoubleArray>()
        events.use { e ->
            Replayer(settings).run(e, null, object : ReplayListener {
                override fun step(step: ReplayStep) {
                    if (step.initialised) out += step.orientation.copyOf()
                }
            })
        }
        return out
    }

    private fun live(reader: SessionReader): List<DoubleArray> {
        val out = ArrayList<DoubleArray>()
        reader.stream(SessionStream.ORIENTATION).use { e -> while (e.next()) out += e.values.copyOf(4) }
        return out
    }

    /** Rotation angle between two unit quaternions, degrees (from the chord, exact for tiny differences). */
    private fun angleDeg(a: DoubleArray, b: DoubleArray): Double {
        val sign = if (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] < 0) -1.0 else 1.0
        val chord = sqrt((0..3).sumOf { (a[it] - sign * b[it]).let { d -> d * d } })
        return Math.toDegrees(4 * asin((chord / 2).coerceAtMost(1.0)))
    }

    private fun worst(a: List<DoubleArray>, b: List<DoubleArray>): Double {
        assertEquals(a.size, b.size)
        return a.indices.maxOf { angleDeg(a[it], b[it]) }
    }

    @Test
    fun `with the switch on, the live filter runs on the corrected streams, meta_json says so and replay reproduces it`() {
        store(calibration, useLive = true)
        val stored = graph.graph.calibrationStore.calibration.value!!
        val c = startService()
        assertEquals(stored, graph.capture.calibrationInUse())
        val trueField = deliverMotion(10.0)
        // The live screen's field is the corrected one (the true field), not Android's calibrated stream.
        val shown = graph.capture.state.value.magneticFieldUt!!
        assertEquals(trueField.norm(), shown, 1e-3)
        assertTrue(abs(shown - (trueField + hardIron - androidHardIron).norm()) > 1.0)
        val dir = stop(c)

        SessionReader.open(dir.toPath()).use { r ->
            assertEquals(SessionCalibration(stored, appliedInLiveFilter = true), r.metadata.calibration)
            // Raw streams stay raw: every stream recorded as delivered.
            assertEquals(1000L, r.metadata.streams.getValue(SessionStream.GYROSCOPE).samples)
            assertEquals(1000L, r.metadata.streams.getValue(SessionStream.GYROSCOPE_UNCALIBRATED).samples)
            val live = live(r)
            assertEquals(1000, live.size)
            val withCalibration = replay(r, CalibratedEvents(r.events(), r.metadata.calibration!!.calibration, r.streams))
            val plain = replay(r, r.events())
            val same = worst(live, withCalibration)
            val other = worst(live, plain)
            println("live filter with the calibration: replay with it within %.2e°, replay without it %.2f° away".format(same, other))
            assertTrue("replay with the recorded calibration: $same°", same < 1e-4)
            assertTrue("replay on Android's calibrated streams: $other°", other > 0.5)
        }
    }

    @Test
    fun `with the switch off, the live filter reads Android's calibrated streams and meta_json still holds the calibration`() {
        store(calibration, useLive = false)
        val c = startService()
        assertNull(graph.capture.calibrationInUse())
        val trueField = deliverMotion(3.0)
        assertEquals((trueField + hardIron - androidHardIron).norm(), graph.capture.state.value.magneticFieldUt!!, 1e-3)
        val dir = stop(c)
        SessionReader.open(dir.toPath()).use { r ->
            val recorded = r.metadata.calibration!!
            assertFalse(recorded.appliedInLiveFilter)
            assertEquals(graph.graph.calibrationStore.calibration.value, recorded.calibration)
            assertTrue(worst(live(r), replay(r, r.events())) < 1e-4)
        }
        // Turned on between recordings: the live view applies it from the next batch.
        graph.graph.calibrationStore.setUseInLiveFilter(true)
        graph.capture.acquire()
        graph.pump()
        assertEquals(graph.graph.calibrationStore.calibration.value, graph.capture.calibrationInUse())
        graph.capture.release()
    }

    @Test
    fun `a recording started before the stores are read waits for them, and meta_json has the stored settings and calibration`() {
        store(calibration, useLive = true)
        val chosen = FilterSettings(beta = 0.05, mode = FilterMode.IMU, restBiasEstimation = false)
        graph.graph.settingsRepository.update(graph.graph.settings.value.copy(filter = chosen))
        graph.settle()
        val stored = graph.graph.calibrationStore.calibration.value!!
        // The process starts again and Record is pressed before the disk executor has read the stores.
        graph = TestGraph(loadStores = false)
        assertNull(graph.graph.calibrationStore.calibration.value)
        val intent = Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START)
        val c = Robolectric.buildService(RecordingService::class.java, intent).create().startCommand(0, 1)
        assertTrue(graph.graph.recordings.state.value is RecordingState.Preparing)
        graph.settle()
        assertTrue(graph.graph.recordings.state.value is RecordingState.Active)
        assertEquals(stored, graph.capture.calibrationInUse())
        deliverMotion(3.0)
        val dir = stop(c)
        SessionReader.open(dir.toPath()).use { r ->
            assertEquals(SessionCalibration(stored, appliedInLiveFilter = true), r.metadata.calibration)
            // The user's settings, not the defaults, ran live and are in meta.json (with the gyroscope's range for the saturation).
            assertEquals(graph.capture.filterSettingsFor(graph.graph.settings.value), r.metadata.filterSettings)
            assertEquals(chosen.copy(gyroSaturation = r.metadata.filterSettings!!.gyroSaturation), r.metadata.filterSettings)
            // Replayed with them, the recording gives the live orientation; with the defaults it does not.
            val events = { CalibratedEvents(r.events(), stored, r.streams) }
            val same = worst(live(r), replay(r, events()))
            val defaults = worst(live(r), replay(r, events(), FilterSettings()))
            println("user's settings: replay with meta.json's within %.2e° of live, with the defaults %.2f° away".format(same, defaults))
            assertTrue("replay with meta.json's settings: $same°", same < 1e-4)
            assertTrue("replay with the defaults: $defaults°", defaults > 1.0)
        }
    }

    @Test
    fun `calibration and live screen together register each sensor once, and the calibration gets the capture's events`() {
        val main = Robolectric.buildActivity(MainActivity::class.java).setup()
        assertEquals(1, sensors.listeners.size)
        val listener = sensors.listeners.single()
        val cal = Robolectric.buildActivity(CalibrationActivity::class.java).setup()
        cal.get().findViewById<View>(R.id.primary_action).performClick()
        graph.settle()
        assertEquals(CalibrationStage.COLLECTING, cal.get().viewModel.state.value.stage)
        assertEquals(listOf(listener), sensors.listeners)
        all.values.forEach { assertTrue(sensors.hasListener(listener, it)) }
        // The live screen goes to the background: the calibration still holds the capture.
        main.pause().stop()
        graph.settle()
        assertEquals(listOf(listener), sensors.listeners)
        deliverMotion(2.0)
        graph.settle()
        // Published every 0.2 s of sensor time: the last publication is at most 20 readings old.
        val shown = cal.get().viewModel.state.value.magSamples
        assertTrue("$shown readings shown", shown in 181L..200L)
        assertEquals(SessionStream.MAGNETOMETER_UNCALIBRATED, cal.get().viewModel.state.value.magStream)
        cal.pause().stop()
        graph.settle()
        assertTrue("unregistered when neither screen is visible", sensors.listeners.isEmpty())
        cal.destroy()
        main.destroy()
    }

    @Test
    fun `a still recording from the calibration screen records accelerometer and gyroscope at the fastest rate, marked for fusion allan`() {
        val cal = Robolectric.buildActivity(CalibrationActivity::class.java).setup()
        val a = cal.get()
        a.findViewById<View>(R.id.step_still).performClick()
        graph.settle()
        assertEquals(a.getString(R.string.calibration_still_ready), a.findViewById<TextView>(R.id.instruction).text.toString())
        a.findViewById<View>(R.id.primary_action).performClick()
        val started = shadowOf(app).nextStartedService
        assertTrue(started.getBooleanExtra(RecordingService.EXTRA_STILL, false))
        val c = Robolectric.buildService(RecordingService::class.java, started).create().startCommand(0, 1)
        graph.settle()
        val active = graph.graph.recordings.state.value as RecordingState.Active
        assertTrue(active.still)
        // Only the streams it writes are registered (the rotation vectors are not).
        val listener = sensors.listeners.single()
        assertEquals(RecordingService.STILL_STREAMS, all.filterValues { sensors.hasListener(listener, it) }.keys)
        deliverMotion(2.0)
        for (k in 0 until 10) send(SessionStream.ROTATION_VECTOR, 4_000_000_000L + k * 10_000_000L, floatArrayOf(0f, 0f, 0f, 1f, 0.1f))
        graph.pump()
        graph.clock.elapsedNs += 754_000_000_000L
        shadowOf(android.os.Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(1))
        assertEquals(a.getString(R.string.calibration_still_stop), a.findViewById<TextView>(R.id.primary_action).text.toString())
        val progress = a.findViewById<TextView>(R.id.progress_text).text.toString()
        assertTrue(progress, progress.startsWith("12:34 recorded · "))
        // A reader that stays after the recording (as the live screen would) gets every sensor back.
        graph.capture.acquire()
        val dir = stop(c)
        assertEquals(all.keys, all.filterValues { sensors.hasListener(sensors.listeners.single(), it) }.keys)
        graph.capture.release()
        SessionReader.open(dir.toPath()).use { r ->
            assertTrue(r.metadata.stillRecording)
            val recorded = r.streams.filter { it in SensorStreams.all }.toSet()
            assertTrue("$recorded", recorded.containsAll(listOf(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE_UNCALIBRATED)))
            assertTrue("$recorded", RecordingService.STILL_STREAMS.containsAll(recorded)) // not the rotation vector
            assertTrue(r.metadata.sensors.all { it.requestedPeriodUs == 0 }) // SENSOR_DELAY_FASTEST
            assertEquals(RecordingService.STILL_STREAMS, r.metadata.sensors.map { it.stream }.toSet())
        }
        graph.settle()
        val result = a.findViewById<TextView>(R.id.result).text.toString()
        assertTrue(result, result.startsWith("Saved as ${dir.name}"))
        cal.pause().stop().destroy()
    }
}
