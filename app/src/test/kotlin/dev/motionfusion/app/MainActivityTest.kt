package dev.motionfusion.app

import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.widget.TextView
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
import org.robolectric.annotation.GraphicsMode
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowSensorManager

/** The path from SensorEvent to the screen, with the sensors ShadowSensorManager provides. */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class MainActivityTest {
    private lateinit var sensors: ShadowSensorManager
    private lateinit var acc: Sensor
    private lateinit var gyro: Sensor
    private lateinit var mag: Sensor

    @Before
    fun addSensors() {
        val sm = RuntimeEnvironment.getApplication().getSystemService(SensorManager::class.java)
        sensors = shadowOf(sm)
        acc = SensorBuilder.newBuilder().setType(Sensor.TYPE_ACCELEROMETER).setName("Test accelerometer").build()
        gyro = SensorBuilder.newBuilder().setType(Sensor.TYPE_GYROSCOPE).setName("Test gyroscope").build()
        mag = SensorBuilder.newBuilder().setType(Sensor.TYPE_MAGNETIC_FIELD).setName("Test magnetometer").build()
    }

    private fun send(sensor: Sensor, t: Long, vararg v: Float) {
        sensors.sendSensorEventToListeners(
            SensorEventBuilder.newBuilder().setSensor(sensor).setValues(v).setTimestamp(t).setAccuracy(SensorManager.SENSOR_STATUS_ACCURACY_HIGH).build(),
        )
    }

    private fun idle() = shadowOf(Looper.getMainLooper()).idle()

    private fun MainActivity.text(id: Int): String = findViewById<TextView>(id).text.toString()

    private fun start(vararg present: Sensor): MainActivity {
        present.forEach(sensors::addSensor)
        val activity = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        idle()
        return activity
    }

    @Test
    fun `listeners are registered for all three sensors while visible`() {
        val controller = Robolectric.buildActivity(MainActivity::class.java)
        listOf(acc, gyro, mag).forEach(sensors::addSensor)
        controller.setup()
        idle()
        assertEquals(1, sensors.listeners.size)
        val listener = sensors.listeners.single()
        listOf(acc, gyro, mag).forEach { assertTrue(sensors.hasListener(listener, it)) }
        controller.pause().stop()
        idle()
        assertTrue("listeners unregistered after onStop", sensors.listeners.isEmpty())
        controller.destroy()
    }

    @Test
    fun `flat phone with its top towards magnetic north`() {
        val a = start(acc, gyro, mag)
        Screenshots.capture(a, "main-waiting")
        send(acc, 1_000_000, 0f, 0f, 9.81f)
        send(gyro, 1_000_500, 0.01f, -0.02f, 0.03f)
        send(mag, 1_001_000, 0f, 22f, -40f)
        idle()
        assertEquals("0.0°", a.text(R.id.azimuth))
        assertEquals("0.0°", a.text(R.id.pitch))
        assertEquals("0.0°", a.text(R.id.roll))
        assertTrue(a.text(R.id.accelerometer).contains("9.810"))
        assertTrue(a.text(R.id.gyroscope).contains("-0.020"))
        assertTrue(a.text(R.id.magnetometer).contains("-40.000"))
        Screenshots.capture(a, "main-flat-north")
    }

    @Test
    fun `top towards east reads azimuth 90 and tilting changes pitch and roll`() {
        val a = start(acc, gyro, mag)
        // North is on the phone's left (-x) when its top points east.
        send(acc, 1, 0f, 0f, 9.81f)
        send(mag, 2, -22f, 0f, -40f)
        idle()
        assertEquals("90.0°", a.text(R.id.azimuth))
        // Top edge raised by 30°: gravity (up in the specific force) leans towards +y.
        val s = Math.sin(Math.toRadians(30.0)).toFloat() * 9.81f
        val c = Math.cos(Math.toRadians(30.0)).toFloat() * 9.81f
        send(acc, 3, 0f, s, c)
        idle()
        assertEquals("-30.0°", a.text(R.id.pitch))
        assertEquals("0.0°", a.text(R.id.roll))
        // Right edge raised by 20° instead.
        val s2 = Math.sin(Math.toRadians(20.0)).toFloat() * 9.81f
        val c2 = Math.cos(Math.toRadians(20.0)).toFloat() * 9.81f
        send(acc, 4, -s2, 0f, c2)
        idle()
        assertEquals("20.0°", a.text(R.id.roll))
        Screenshots.capture(a, "main-tilted")
    }

    @Test
    fun `free fall gives no orientation and a reason`() {
        val a = start(acc, gyro, mag)
        send(acc, 1, 0f, 0f, 0.1f)
        send(mag, 2, 0f, 22f, -40f)
        idle()
        assertEquals("—", a.text(R.id.azimuth))
        assertEquals(a.getString(R.string.orientation_unavailable), a.text(R.id.orientation_status))
    }

    @Test
    fun `a device without gyroscope says so`() {
        val a = start(acc, mag)
        assertEquals(a.getString(R.string.sensor_missing), a.text(R.id.gyroscope))
        assertFalse(a.text(R.id.accelerometer) == a.getString(R.string.sensor_missing))
        Screenshots.capture(a, "main-no-gyroscope")
    }
}
