package dev.motionfusion.app

import android.app.Activity
import android.hardware.SensorManager
import android.os.Bundle
import android.os.Handler
import android.os.Looper
import android.widget.TextView
import dev.motionfusion.app.live.LiveModel
import dev.motionfusion.app.live.LiveState
import dev.motionfusion.app.live.OrientationReading
import dev.motionfusion.app.live.displayDegrees
import dev.motionfusion.app.record.RecordBar
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorSource
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Job
import kotlinx.coroutines.MainScope
import kotlinx.coroutines.cancel
import kotlinx.coroutines.launch

/**
 * The live screen: each sensor's latest values and the accelerometer/magnetometer
 * orientation. Sensors are listened to only while the screen is visible (onStart..onStop).
 */
class MainActivity : Activity() {
    private lateinit var source: SensorSource
    private lateinit var model: LiveModel
    private val scope: CoroutineScope = MainScope()
    private var capture: Job? = null
    private val mainHandler = Handler(Looper.getMainLooper())
    private var renderPending = false
    private val render = Runnable {
        renderPending = false
        show(model.state())
    }

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_main)
        RecordBar.attach(this, findViewById(R.id.record_bar))
        source = SensorSource(getSystemService(SensorManager::class.java))
        model = LiveModel(SensorKind.entries.toSet() - source.availableKinds())
        show(model.state())
    }

    override fun onStart() {
        super.onStart()
        capture = scope.launch {
            source.samples(SensorKind.entries.toSet(), SensorManager.SENSOR_DELAY_GAME).collect { sample ->
                model.onSample(sample)
                // Many samples per frame: draw once for all that arrived since the last draw.
                if (!renderPending) {
                    renderPending = true
                    mainHandler.post(render)
                }
            }
        }
    }

    override fun onStop() {
        capture?.cancel()
        capture = null
        super.onStop()
    }

    override fun onDestroy() {
        scope.cancel()
        mainHandler.removeCallbacks(render)
        super.onDestroy()
    }

    private fun show(state: LiveState) {
        val angleViews = listOf(R.id.azimuth, R.id.pitch, R.id.roll).map { findViewById<TextView>(it) }
        val status = findViewById<TextView>(R.id.orientation_status)
        when (val o = state.orientation) {
            is OrientationReading.Angles -> {
                val values = listOf(o.azimuthDeg, o.pitchDeg, o.rollDeg)
                angleViews.zip(values).forEach { (v, deg) -> v.text = getString(R.string.angle_deg, displayDegrees(deg)) }
                status.setText(R.string.orientation_ok)
            }
            else -> {
                angleViews.forEach { it.setText(R.string.angle_unknown) }
                status.setText(
                    if (o == OrientationReading.Undefined) R.string.orientation_unavailable else R.string.orientation_waiting,
                )
            }
        }
        showValues(R.id.accelerometer, SensorKind.ACCELEROMETER, state)
        showValues(R.id.gyroscope, SensorKind.GYROSCOPE, state)
        showValues(R.id.magnetometer, SensorKind.MAGNETOMETER, state)
    }

    private fun showValues(viewId: Int, kind: SensorKind, state: LiveState) {
        val view = findViewById<TextView>(viewId)
        val s = state.latest[kind]
        view.text = when {
            s != null -> getString(R.string.vector_values, s.x, s.y, s.z)
            kind in state.missing -> getString(R.string.sensor_missing)
            else -> getString(R.string.no_data)
        }
    }
}
