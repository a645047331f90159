package dev.motionfusion.app

import dev.motionfusion.app.platform.Sdks
import org.robolectric.annotation.Config
import android.content.Context
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.view.Surface
import android.view.View
import android.widget.TextView
import dev.motionfusion.app.settings.AngleConvention
import dev.motionfusion.app.fusion.Capture
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.ui.AnglePlotView
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.settings.SettingsStore
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNotNull
import org.junit.Assert.assertNotSame
import org.junit.Assert.assertSame
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.android.controller.ActivityController
import org.robolectric.annotation.GraphicsMode
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowDisplay
import org.robolectric.shadows.ShadowSensorManager
import java.time.Duration
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import kotlin.math.cos
import kotlin.math.sin

/**
 * From SensorEvents (ShadowSensorManager) through the fusion engine's thread to the text on
 * screen. Angles on screen are checked within [TOL] degrees: the screen shows 0.1° and the
 * filter, started from the first samples, stays within 0.05° of the exact angle on these
 * noise-free inputs.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class MainActivityTest {
    private lateinit var sensors: ShadowSensorManager
    private lateinit var acc: Sensor
    private lateinit var gyro: Sensor
    private lateinit var mag: Sensor
    private lateinit var rv: Sensor
    private lateinit var grv: Sensor
    private var t = 1_000_000_000L

    @Before
    fun addSensors() {
        val sm = RuntimeEnvironment.getApplication().getSystemService(SensorManager::class.java)
        sensors = shadowOf(sm)
        acc = SensorBuilder.newBuilder().setType(Sensor.TYPE_ACCELEROMETER).setName("Test accelerometer").build()
        gyro = SensorBuilder.newBuilder().setType(Sensor.TYPE_GYROSCOPE).setName("Test gyroscope").build()
        mag = SensorBuilder.newBuilder().setType(Sensor.TYPE_MAGNETIC_FIELD).setName("Test magnetometer").build()
        rv = SensorBuilder.newBuilder().setType(Sensor.TYPE_ROTATION_VECTOR).setName("Test rotation vector").build()
        grv = SensorBuilder.newBuilder().setType(Sensor.TYPE_GAME_ROTATION_VECTOR).setName("Test game rotation vector").build()
    }

    private fun send(sensor: Sensor, time: Long, v: FloatArray, accuracy: Int = SensorManager.SENSOR_STATUS_ACCURACY_HIGH) {
        sensors.sendSensorEventToListeners(
            SensorEventBuilder.newBuilder().setSensor(sensor).setValues(v).setTimestamp(time).setAccuracy(accuracy).build(),
        )
    }

    private lateinit var graph: TestGraph

    private fun engine(): Capture = graph.capture

    /** Lets the capture fold in what was sent, then the main thread draw a frame. */
    private fun frame() {
        graph.pump()
        shadowOf(Looper.getMainLooper()).idle()
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofMillis(50))
    }

    /**
     * 0.3 s of a phone held still: [up] is the accelerometer (up in device coordinates, m/s²),
     * [field] the magnetometer (µT), sampled together at 100 Hz with a still gyroscope.
     */
    private fun holdStill(up: FloatArray, field: FloatArray?, magAccuracy: Int = SensorManager.SENSOR_STATUS_ACCURACY_HIGH, withGyro: Boolean = true) {
        repeat(30) {
            send(acc, t, up)
            if (field != null) send(mag, t + 1000, field, magAccuracy)
            if (withGyro) send(gyro, t + 2000, floatArrayOf(0f, 0f, 0f))
            t += 10_000_000L
        }
        frame()
    }

    private fun start(vararg present: Sensor): ActivityController<MainActivity> {
        present.forEach(sensors::addSensor)
        graph = TestGraph()
        val c = Robolectric.buildActivity(MainActivity::class.java).setup()
        frame()
        return c
    }

    private fun MainActivity.text(id: Int): String = findViewById<TextView>(id).text.toString()

    /** The number in a "12.3°" text. */
    private fun MainActivity.deg(id: Int): Double = text(id).removeSuffix("°").toDouble()

    private fun assertAngle(expected: Double, actual: Double) {
        val d = ((expected - actual) % 360.0 + 540.0) % 360.0 - 180.0
        assertEquals("expected $expected°, shown $actual°", 0.0, d, TOL)
    }

    private fun MainActivity.assertAngles(yaw: Double?, pitch: Double, roll: Double?) {
        yaw?.let { assertAngle(it, deg(R.id.yaw)) }
        assertAngle(pitch, deg(R.id.pitch))
        roll?.let { assertAngle(it, deg(R.id.roll)) }
    }

    private fun setDisplayRotation(r: Int) {
        shadowOf(ShadowDisplay.getDefaultDisplay()).setRotation(r)
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    fun `each sensor is registered once while visible and removed after onStop`() {
        val c = start(acc, gyro, mag, rv, grv)
        assertEquals(1, sensors.listeners.size)
        val listener = sensors.listeners.single()
        listOf(acc, gyro, mag, rv, grv).forEach { assertTrue(sensors.hasListener(listener, it)) }
        val e = engine()
        assertTrue(e.isRunning)
        c.pause().stop()
        shadowOf(Looper.getMainLooper()).idle()
        assertTrue("listeners unregistered after onStop", sensors.listeners.isEmpty())
        assertFalse(e.isRunning)
        c.destroy()
    }

    @Test
    fun `flat with the top towards magnetic north reads 0, 0, 0`() {
        val c = start(acc, gyro, mag, rv, grv)
        Screenshots.capture(c.get(), "live-waiting")
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 22f, -40f))
        send(rv, t, floatArrayOf(0f, 0f, 0f, 1f, 0.1f))
        send(grv, t, floatArrayOf(0f, 0f, 0f, 1f))
        frame()
        val a = c.get()
        a.assertAngles(0.0, 0.0, 0.0)
        assertEquals(a.getString(R.string.mode_marg), a.text(R.id.mode_explanation))
        assertEquals(View.GONE, a.findViewById<View>(R.id.mag_warning).visibility)
        assertTrue(a.text(R.id.mag_status), a.text(R.id.mag_status).contains("45.7 µT"))
        assertTrue(a.text(R.id.rv_difference), a.text(R.id.rv_difference).contains("0.0° apart"))
        assertTrue(a.text(R.id.rv_angles), a.text(R.id.rv_angles).endsWith("heading accuracy ±5.7°"))
        Screenshots.capture(a, "live-flat")
    }

    @Test
    fun `pitched 90 degrees (upright, facing north) reads pitch -90`() {
        val c = start(acc, gyro, mag)
        // Upright: up is the device's +y; the back (−z) faces north, the field dips 40 µT down (−y).
        holdStill(floatArrayOf(0f, 9.81f, 0f), floatArrayOf(0f, -40f, -22f))
        // Azimuth and roll are not separable at ±90° pitch (gimbal lock): only pitch is checked.
        c.get().assertAngles(null, -90.0, null)
    }

    @Test
    fun `yawed 90 degrees (top towards east) reads azimuth 90`() {
        val c = start(acc, gyro, mag)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(-22f, 0f, -40f))
        c.get().assertAngles(90.0, 0.0, 0.0)
    }

    @Test
    fun `upside down reads roll 180`() {
        val c = start(acc, gyro, mag)
        // Screen down, top north: turned 180° about the device's y axis.
        holdStill(floatArrayOf(0f, 0f, -9.81f), floatArrayOf(0f, 22f, 40f))
        c.get().assertAngles(0.0, 0.0, 180.0)
    }

    @Test
    fun `tilted, in aerospace angles, beside the rotation vector`() {
        offMainThread { SettingsStore(RuntimeEnvironment.getApplication()).save(LiveSettings(convention = AngleConvention.AEROSPACE)) }
        val c = start(acc, gyro, mag, rv, grv)
        // Top edge raised by 30° (rotation about device x), top towards north.
        val s = sin(Math.toRadians(30.0)).toFloat()
        val co = cos(Math.toRadians(30.0)).toFloat()
        val up = floatArrayOf(0f, 9.81f * s, 9.81f * co)
        // Field: 22 µT north (horizontal), 40 µT down, in device coordinates (y' = cos·N + sin·U...).
        val field = floatArrayOf(0f, 22f * co - 40f * s, -22f * s - 40f * co)
        holdStill(up, field)
        // The phone's rotation vector: the same tilt but 3° further east.
        val q = Quaternion.fromAxisAngle(Vector3.UNIT_Z, Math.toRadians(-3.0)) * Quaternion.fromAxisAngle(Vector3.UNIT_X, Math.toRadians(30.0))
        send(rv, t, floatArrayOf(q.x.toFloat(), q.y.toFloat(), q.z.toFloat(), q.w.toFloat(), 0.05f))
        frame()
        val a = c.get()
        assertEquals(a.getString(R.string.yaw), a.text(R.id.yaw_label))
        a.assertAngles(0.0, 30.0, 0.0)
        assertTrue(a.text(R.id.rv_difference), a.text(R.id.rv_difference).contains("3.0° apart (tilt alone 0.0°)"))
        assertTrue(a.text(R.id.rv_angles), a.text(R.id.rv_angles).startsWith("Yaw 3.0°"))
        Screenshots.capture(a, "live-tilted-aerospace")
    }

    @Test
    fun `each display rotation gives the angles of the screen as the user sees it`() {
        val c = start(acc, gyro, mag)
        val s = sin(Math.toRadians(30.0)).toFloat()
        val co = cos(Math.toRadians(30.0)).toFloat()
        // Device top raised by 30°, device top towards north.
        holdStill(floatArrayOf(0f, 9.81f * s, 9.81f * co), floatArrayOf(0f, 22f * co - 40f * s, -22f * s - 40f * co))
        val a = c.get()
        a.assertAngles(0.0, -30.0, 0.0)
        // ROTATION_90: the screen's up is the device's right edge (east); the device top is the screen's left edge.
        setDisplayRotation(Surface.ROTATION_90); frame()
        a.assertAngles(90.0, 0.0, 30.0)
        setDisplayRotation(Surface.ROTATION_180); frame()
        a.assertAngles(180.0, 30.0, 0.0)
        setDisplayRotation(Surface.ROTATION_270); frame()
        a.assertAngles(270.0, 0.0, -30.0)
        setDisplayRotation(Surface.ROTATION_0); frame()
        a.assertAngles(0.0, -30.0, 0.0)
    }

    @Test
    fun `landscape screen`() {
        RuntimeEnvironment.setQualifiers("+land")
        val c = start(acc, gyro, mag, rv)
        setDisplayRotation(Surface.ROTATION_90)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 22f, -40f))
        c.get().assertAngles(90.0, 0.0, 0.0)
        Screenshots.capture(c.get(), "live-landscape", width = 1920, height = 1080)
    }

    @Test
    fun `walking through a building with the switch on, the heading is shown held on the gyroscope without a figure-8 hint`() {
        offMainThread { SettingsStore(RuntimeEnvironment.getApplication()).save(LiveSettings(filter = FilterSettings(magTrustSpread = FilterSettings.BUILDINGS_TRUST_SPREAD))) }
        val c = start(acc, gyro, mag, rv)
        // Level and still for 40 s in a field whose strength wanders by up to ±15 % (a building's steel passing by).
        for (i in 0..4000) {
            val k = (1.0 + 0.15 * sin(i * 0.02) * sin(i * 0.0071)).toFloat()
            send(acc, t, floatArrayOf(0f, 0f, 9.81f))
            send(mag, t + 1000, floatArrayOf(0f, 22f * k, -40f * k))
            send(gyro, t + 2000, floatArrayOf(0f, 0f, 0f))
            t += 10_000_000L
        }
        frame()
        val a = c.get()
        assertEquals(View.VISIBLE, a.findViewById<View>(R.id.mag_warning).visibility)
        assertTrue(a.text(R.id.mag_warning), a.text(R.id.mag_warning).contains("holding the heading on the gyroscope"))
        assertEquals(View.GONE, a.findViewById<View>(R.id.figure8_hint).visibility)
        Screenshots.capture(a, "live-buildings-held")
    }

    @Test
    fun `a weak calibration and a strong field show the warning and the figure-8 hint`() {
        val c = start(acc, gyro, mag, rv)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 60f, -70f), magAccuracy = SensorManager.SENSOR_STATUS_ACCURACY_LOW)
        val a = c.get()
        assertEquals(View.VISIBLE, a.findViewById<View>(R.id.mag_warning).visibility)
        assertEquals(View.VISIBLE, a.findViewById<View>(R.id.figure8_hint).visibility)
        assertTrue(a.text(R.id.mag_warning), a.text(R.id.mag_warning).contains("accuracy is low"))
        assertTrue(a.text(R.id.mag_warning), a.text(R.id.mag_warning).contains("92.2 µT"))
        Screenshots.capture(a, "live-mag-warning")
    }

    @Test
    fun `without gyroscope the accelerometer and magnetometer give the orientation, and the screen says so`() {
        val c = start(acc, mag)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(-22f, 0f, -40f), withGyro = false)
        val a = c.get()
        a.assertAngles(90.0, 0.0, 0.0)
        assertEquals(a.getString(R.string.mode_acc_mag), a.text(R.id.mode_explanation))
        val rows = (0 until a.findViewById<android.widget.LinearLayout>(R.id.sensor_list).childCount)
            .map { (a.findViewById<android.widget.LinearLayout>(R.id.sensor_list).getChildAt(it) as TextView).text.toString() }
        assertTrue(rows.toString(), rows.any { it == "Gyroscope: not on this device" })
        // A driver without a vendor string (as here) shows the name alone, without empty or "?" parentheses.
        assertTrue(rows.toString(), rows.any { it.lineSequence().first() == "Accelerometer: Test accelerometer" })
        assertTrue(a.text(R.id.rv_angles), a.text(R.id.rv_angles) == a.getString(R.string.rv_missing))
        Screenshots.capture(a, "live-no-gyroscope")
    }

    @Test
    fun `without magnetometer the filter runs 6D with a relative heading`() {
        val c = start(acc, gyro)
        holdStill(floatArrayOf(0f, 0f, 9.81f), null)
        val a = c.get()
        a.assertAngles(0.0, 0.0, 0.0) // the relative heading starts at 0
        assertEquals(a.getString(R.string.mode_imu_no_mag), a.text(R.id.mode_explanation))
        assertEquals(a.getString(R.string.compass_relative_description, "0°"), a.findViewById<View>(R.id.compass).contentDescription)
        assertTrue(a.text(R.id.convention_note).contains(a.getString(R.string.convention_relative_heading)))
        assertEquals(FilterMode.IMU, engine().filterSettingsInUse().mode)
        // No north: the 3-D phone's ground ring has no cardinal points either.
        assertFalse(a.findViewById<dev.motionfusion.app.ui.PhoneModelView>(R.id.phone_model).northKnown)
        Screenshots.capture(a, "live-no-magnetometer")
    }

    @Test
    fun `with the accelerometer alone there is tilt and no heading`() {
        val c = start(acc)
        val s = sin(Math.toRadians(20.0)).toFloat()
        val co = cos(Math.toRadians(20.0)).toFloat()
        holdStill(floatArrayOf(-9.81f * s, 0f, 9.81f * co), null, withGyro = false)
        val a = c.get()
        a.assertAngles(null, 0.0, 20.0)
        assertEquals(a.getString(R.string.mode_tilt), a.text(R.id.mode_explanation))
        assertEquals(a.getString(R.string.compass_unknown_description), a.findViewById<View>(R.id.compass).contentDescription)
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    fun `the rate and jitter achieved are shown per sensor`() {
        val c = start(acc, gyro, mag)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 22f, -40f))
        val list = c.get().findViewById<android.widget.LinearLayout>(R.id.sensor_list)
        val gyroRow = (0 until list.childCount).map { (list.getChildAt(it) as TextView).text.toString() }.first { it.startsWith("Gyroscope") }
        assertTrue(gyroRow, gyroRow.contains("Test gyroscope"))
        assertTrue(gyroRow, gyroRow.contains("requested 100 Hz · achieved 100.0 Hz · jitter 0.00 ms · accuracy high"))
        // Nothing conflated on the data path: every event reached the fusion.
        val stats = engine().state.value.sensors
        for (k in listOf(SensorKind.ACCELEROMETER, SensorKind.GYROSCOPE, SensorKind.MAGNETOMETER)) assertEquals(30L, stats.getValue(k).samples)
        assertEquals(29L, engine().state.value.filterSteps)
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    fun `a new requested rate re-registers the listeners and samples keep flowing`() {
        val c = start(acc, gyro, mag)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 22f, -40f))
        graph.graph.settingsRepository.update(LiveSettings(rate = SamplingRate.Delay.GAME))
        frame()
        val after = sensors.listeners.single()
        listOf(acc, gyro, mag).forEach { assertTrue(sensors.hasListener(after, it)) }
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 22f, -40f))
        assertEquals(60L, engine().state.value.sensors.getValue(SensorKind.GYROSCOPE).samples)
        // The filter was not rebuilt by a rate change: it kept stepping (29 steps, then 30 more).
        assertEquals(59L, engine().state.value.filterSteps)
        c.get().assertAngles(0.0, 0.0, 0.0)
    }

    @Test
    fun `the filter survives re-creation of the activity`() {
        val c = start(acc, gyro, mag)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(-22f, 0f, -40f))
        val e = engine()
        val steps = e.state.value.filterSteps
        assertTrue(steps > 0)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(-22f, 0f, -40f))
        val plotted = c.get().findViewById<AnglePlotView>(R.id.plot)
        val points = plotted.pointCount
        val span = plotted.spanSeconds
        assertTrue("plotted before the rotation: $points", points > 1)
        c.recreate()
        frame()
        assertSame(e, engine())
        val a = c.get()
        a.assertAngles(90.0, 0.0, 0.0) // shown at once, before any new sample
        // The new activity's plot draws the history the ViewModel kept, not an empty one.
        val plot = a.findViewById<AnglePlotView>(R.id.plot)
        assertNotSame(plotted, plot)
        assertEquals(points, plot.pointCount)
        assertEquals(span, plot.spanSeconds, 0.0)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(-22f, 0f, -40f))
        assertTrue("the same filter keeps stepping", e.state.value.filterSteps > steps)
        a.assertAngles(90.0, 0.0, 0.0)
    }

    @Test
    fun `a settings change reaches the running filter and the screen`() {
        val c = start(acc, gyro, mag)
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 22f, -40f))
        graph.graph.settingsRepository.update(LiveSettings(filter = FilterSettings(mode = FilterMode.IMU, beta = 0.2)))
        frame()
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 22f, -40f))
        val a = c.get()
        assertEquals(FilterMode.IMU, engine().filterSettingsInUse().mode)
        assertEquals(0.2, engine().filterSettingsInUse().beta, 0.0)
        assertEquals(a.getString(R.string.mode_imu_chosen), a.text(R.id.mode_explanation))
        // Persisted for the next start of the app.
        graph.settle()
        assertEquals(LiveSettings(filter = FilterSettings(mode = FilterMode.IMU, beta = 0.2)), offMainThread { SettingsStore(RuntimeEnvironment.getApplication()).load() })
        assertNotNull(a.text(R.id.yaw))
    }

    /** Sends one 100 Hz sample of each motion sensor for the orientation [q] (device → ENU) turning at [rate] (rad/s, device frame). */
    private fun sendPose(q: Quaternion, rate: FloatArray) {
        val up = q.inverseRotate(Vector3(0.0, 0.0, 9.81))
        val field = q.inverseRotate(Vector3(0.0, 22.0, -40.0))
        send(acc, t, up.toFloatArray())
        send(mag, t + 1000, field.toFloatArray())
        send(gyro, t + 2000, rate)
        t += 10_000_000L
    }

    @Test
    fun `turning and tilting the phone is followed and plotted`() {
        val c = start(acc, gyro, mag, rv)
        val z = Vector3.UNIT_Z
        val x = Vector3.UNIT_X
        holdStill(floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 22f, -40f))
        // 1 s turning clockwise (seen from above) by 60°, then 1 s raising the top edge by 30°,
        // with a frame every 50 ms.
        val yawRate = Math.toRadians(60.0)
        val pitchRate = Math.toRadians(30.0)
        for (i in 1..100) {
            sendPose(Quaternion.fromAxisAngle(z, -yawRate * i / 100.0), floatArrayOf(0f, 0f, -yawRate.toFloat()))
            if (i % 5 == 0) frame()
        }
        for (i in 1..100) {
            val q = Quaternion.fromAxisAngle(z, -yawRate) * Quaternion.fromAxisAngle(x, pitchRate * i / 100.0)
            sendPose(q, floatArrayOf(pitchRate.toFloat(), 0f, 0f))
            if (i % 5 == 0) frame()
        }
        holdStill(
            Quaternion.fromAxisAngle(z, -yawRate).times(Quaternion.fromAxisAngle(x, pitchRate)).inverseRotate(Vector3(0.0, 0.0, 9.81)).toFloatArray(),
            Quaternion.fromAxisAngle(z, -yawRate).times(Quaternion.fromAxisAngle(x, pitchRate)).inverseRotate(Vector3(0.0, 22.0, -40.0)).toFloatArray(),
        )
        val a = c.get()
        a.assertAngles(60.0, -30.0, 0.0)
        Screenshots.capture(a, "live-moving")
    }

    private companion object {
        const val TOL = 0.1
    }
}
