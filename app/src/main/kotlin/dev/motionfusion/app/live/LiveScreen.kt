package dev.motionfusion.app.live

import android.app.Activity
import android.view.View
import android.widget.LinearLayout
import android.widget.TextView
import dev.motionfusion.app.R
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.sensor.SensorInfo
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.label
import dev.motionfusion.app.ui.AnglePlotView
import dev.motionfusion.app.ui.AngleTrace
import dev.motionfusion.app.ui.AttitudeIndicatorView
import dev.motionfusion.app.ui.CompassView
import dev.motionfusion.app.ui.DescriptionThrottle
import dev.motionfusion.app.ui.PhoneModelView
import dev.motionfusion.app.ui.PlotMarker
import dev.motionfusion.app.ui.setTextIfChanged
import java.util.EnumMap
import dev.motionfusion.app.settings.AngleConvention
import dev.motionfusion.app.fusion.EffectiveMode
import dev.motionfusion.app.fusion.FusionMode
import dev.motionfusion.app.fusion.FusionState
import dev.motionfusion.app.fusion.ModeReason

/**
 * Binds the views of activity_main (any of its layouts: they share the ids) to one frame's
 * [FusionState]: texts, the 3D model with the rotation vector's ghost, attitude indicator,
 * compass, plot, rotation vector comparison, magnetometer warnings, filter flags and the
 * per-sensor status. Called on the main thread once per display frame when the state changed;
 * the state may come from anywhere (the engine, or a test's hand-made one).
 */
class LiveScreen(private val activity: Activity, private val sensorInfo: Map<SensorKind, SensorInfo>, plotTrace: AngleTrace = AngleTrace()) {
    private fun text(id: Int): TextView = activity.findViewById(id)

    private val yaw = text(R.id.yaw)
    private val pitch = text(R.id.pitch)
    private val roll = text(R.id.roll)
    private val yawLabel = text(R.id.yaw_label)
    private val anglesRow: View = activity.findViewById(R.id.angles)
    private val modeText = text(R.id.mode_explanation)
    private val conventionNote = text(R.id.convention_note)
    private val attitude: AttitudeIndicatorView = activity.findViewById(R.id.attitude)
    private val compass: CompassView = activity.findViewById(R.id.compass)
    private val plot: AnglePlotView = activity.findViewById(R.id.plot)
    private val model: PhoneModelView = activity.findViewById(R.id.phone_model)
    private val rvAngles = text(R.id.rv_angles)
    private val rvDifference = text(R.id.rv_difference)
    private val magStatus = text(R.id.mag_status)
    private val magWarning = text(R.id.mag_warning)
    private val figure8 = text(R.id.figure8_hint)
    private val filterFlags = text(R.id.filter_flags)
    private val filterBias = text(R.id.filter_bias)
    private val sensorList: LinearLayout = activity.findViewById(R.id.sensor_list)
    private val sensorRows = EnumMap<SensorKind, TextView>(SensorKind::class.java)

    // Descriptions in whole degrees, given to the views at most every 2 s of sample time (TalkBack reads each new one).
    private val anglesDescription = DescriptionThrottle(DescriptionThrottle.LIVE_INTERVAL_NS)
    private val attitudeDescription = DescriptionThrottle(DescriptionThrottle.LIVE_INTERVAL_NS)
    private val compassDescription = DescriptionThrottle(DescriptionThrottle.LIVE_INTERVAL_NS)

    /** Descriptions given to the angles, the attitude indicator and the compass so far (tests count them). */
    internal val descriptionUpdates: Int get() = anglesDescription.updates + attitudeDescription.updates + compassDescription.updates

    init {
        sensorList.removeAllViews()
        for (kind in SensorKind.entries) {
            val row = TextView(activity, null, 0, R.style.Mono)
            row.setPadding(0, dp(4), 0, dp(8))
            sensorList.addView(row, LinearLayout.LayoutParams(LinearLayout.LayoutParams.MATCH_PARENT, LinearLayout.LayoutParams.WRAP_CONTENT))
            sensorRows[kind] = row
        }
        plot.emptyText = activity.getString(R.string.waiting_for_samples)
        plot.trace = plotTrace
    }

    /** Shows [s] for the display rotation [displayRotation] (Surface.ROTATION_*), with [markers] on the plot (sample clock). */
    fun show(s: FusionState, displayRotation: Int, markers: List<PlotMarker> = emptyList()) {
        val ui = LiveUiState.of(s, displayRotation)
        val convention = s.settings.convention
        val yawName = activity.getString(if (convention == AngleConvention.ANDROID) R.string.azimuth else R.string.yaw)
        yawLabel.setTextIfChanged(yawName)
        plot.setYawName(yawName)
        model.setOrientation(ui.orientation, ui.rotationVector)
        model.northKnown = ui.headingQuality != HeadingQuality.RELATIVE
        val a = ui.angles
        if (a != null) {
            yaw.setTextIfChanged(heading(a.yaw))
            pitch.setTextIfChanged(deg(a.pitch))
            roll.setTextIfChanged(deg(a.roll))
            anglesDescription.update(anglesRow, activity.getString(R.string.angles_description, yawName, wholeHeading(a.yaw), wholeDeg(a.pitch), wholeDeg(a.roll)), s.timestampNs, yawName)
        } else {
            val unknown = activity.getString(R.string.angle_unknown)
            for (v in listOf(yaw, pitch, roll)) v.setTextIfChanged(unknown)
            anglesDescription.update(anglesRow, null, s.timestampNs)
        }
        modeText.setTextIfChanged(activity.getString(modeText(s.mode)))
        conventionNote.setTextIfChanged(buildString {
            append(activity.getString(if (convention == AngleConvention.ANDROID) R.string.convention_android_note else R.string.convention_aerospace_note))
            if (ui.headingQuality == HeadingQuality.RELATIVE) append(' ').append(activity.getString(R.string.convention_relative_heading))
        })

        val att = ui.attitude
        attitude.setAttitude(att?.pitch ?: 0.0, att?.roll ?: 0.0, att != null)
        attitudeDescription.update(
            attitude,
            if (att != null) activity.getString(R.string.attitude_description, wholeDeg(att.pitch), wholeDeg(att.roll)) else activity.getString(R.string.attitude_unknown_description),
            s.timestampNs, att != null,
        )
        val h = ui.headingDeg
        compass.setHeading(h ?: 0.0, CompassView.State.valueOf(ui.headingQuality.name))
        compassDescription.update(
            compass,
            when {
                h == null -> activity.getString(R.string.compass_unknown_description)
                ui.headingQuality == HeadingQuality.RELATIVE -> activity.getString(R.string.compass_relative_description, wholeHeading(h))
                else -> activity.getString(R.string.compass_description, wholeHeading(h))
            },
            s.timestampNs, ui.headingQuality,
        )
        if (a != null) {
            val g = ui.rotationVectorAngles
            plot.append(s.timestampNs, a.yaw, a.pitch, a.roll, g?.yaw ?: Double.NaN, g?.pitch ?: Double.NaN, g?.roll ?: Double.NaN)
        }
        plot.setMarkers(markers)

        showRotationVector(s, ui, yawName)
        showMagnetometer(s, ui)
        showFilter(s)
        for (kind in SensorKind.entries) sensorRows[kind]!!.setTextIfChanged(sensorText(kind, s))
    }

    private fun showRotationVector(s: FusionState, ui: LiveUiState, yawName: String) {
        val rva = ui.rotationVectorAngles
        rvAngles.setTextIfChanged(when {
            SensorKind.ROTATION_VECTOR !in sensorInfo -> activity.getString(R.string.rv_missing)
            rva == null -> activity.getString(R.string.rv_waiting)
            else -> activity.getString(R.string.rv_angles, yawName, heading(rva.yaw), deg(rva.pitch), deg(rva.roll)) +
                (s.rotationVectorHeadingAccuracyRad?.let { activity.getString(R.string.rv_heading_accuracy, Math.toDegrees(it)) } ?: "")
        })
        val lines = ArrayList<String>(2)
        val d = ui.differenceDeg
        val t = ui.tiltDifferenceDeg
        if (d != null && t != null) {
            lines += if (s.mode.mode.hasMagneticHeading) {
                activity.getString(R.string.rv_difference, d, t)
            } else {
                activity.getString(R.string.rv_difference_relative, t)
            }
        }
        ui.gameTiltDifferenceDeg?.let { lines += activity.getString(R.string.grv_difference, it) }
        rvDifference.setTextIfChanged(lines.joinToString("\n"))
        rvDifference.visibility = if (lines.isEmpty()) View.GONE else View.VISIBLE
    }

    private fun showMagnetometer(s: FusionState, ui: LiveUiState) {
        val mag = s.sensors[SensorKind.MAGNETOMETER]
        val field = s.magneticFieldUt
        magStatus.setTextIfChanged(when {
            SensorKind.MAGNETOMETER !in sensorInfo -> activity.getString(R.string.sensor_missing, activity.getString(R.string.kind_magnetometer))
            mag == null || field == null -> activity.getString(R.string.sensor_no_data)
            else -> activity.getString(R.string.mag_status, field, accuracy(mag.accuracy))
        })
        val warnings = ui.magWarnings.map {
            when (it) {
                MagWarning.LOW_ACCURACY -> activity.getString(R.string.mag_warning_accuracy, accuracy(mag!!.accuracy))
                MagWarning.FIELD_STRENGTH -> activity.getString(R.string.mag_warning_field, field ?: 0.0)
                MagWarning.DISTURBED -> activity.getString(R.string.mag_warning_disturbed)
            }
        }
        magWarning.setTextIfChanged(warnings.joinToString("\n"))
        magWarning.visibility = if (warnings.isEmpty()) View.GONE else View.VISIBLE
        figure8.visibility = if (ui.showCalibrationHint) View.VISIBLE else View.GONE
    }

    private fun showFilter(s: FusionState) {
        fun flag(b: Boolean) = activity.getString(if (b) R.string.flag_yes else R.string.flag_no)
        filterFlags.setTextIfChanged(activity.getString(R.string.filter_flags, flag(s.atRest), flag(s.magneticDisturbance), flag(s.accelerometerRejected)))
        val b = s.gyroBiasRadS
        filterBias.setTextIfChanged(if (b != null) activity.getString(R.string.filter_bias, b[0], b[1], b[2], s.filterSteps) else "")
        filterBias.visibility = if (b != null) View.VISIBLE else View.GONE
    }

    private fun sensorText(kind: SensorKind, s: FusionState): String {
        val name = activity.getString(kindName(kind))
        val info = sensorInfo[kind] ?: return activity.getString(R.string.sensor_missing, name)
        val head = if (info.vendor.isBlank()) activity.getString(R.string.sensor_line_no_vendor, name, info.name)
        else activity.getString(R.string.sensor_line, name, info.name, info.vendor)
        val st = s.sensors[kind] ?: return head + "\n" + activity.getString(R.string.sensor_no_data)
        val rates = activity.getString(
            R.string.sensor_rates,
            requested(s.settings.rate),
            if (st.rateHz.isNaN()) activity.getString(R.string.unknown) else activity.getString(R.string.rate_hz, st.rateHz),
            if (st.jitterMs.isNaN()) activity.getString(R.string.unknown) else activity.getString(R.string.jitter_ms, st.jitterMs),
            accuracy(st.accuracy),
        )
        val values = if (kind.isRotationVector) {
            activity.getString(R.string.sensor_values4, st.x, st.y, st.z, st.w)
        } else {
            activity.getString(R.string.sensor_values, st.x, st.y, st.z, kind.unit)
        }
        return "$head\n$rates\n$values"
    }

    private fun requested(r: SamplingRate): String = r.label(activity)

    private fun deg(v: Double): String = activity.getString(R.string.angle_deg, displayDegrees(v))
    private fun heading(v: Double): String = activity.getString(R.string.angle_deg, displayHeading(v))
    private fun wholeDeg(v: Double): String = activity.getString(R.string.angle_deg_whole, Math.rint(displayDegrees(v)).let { if (it == -0.0) 0.0 else it })
    private fun wholeHeading(v: Double): String = activity.getString(R.string.angle_deg_whole, Math.rint(displayHeading(v)) % 360.0)

    private fun accuracy(a: Int): String = activity.getString(
        when (a) {
            -1 -> R.string.accuracy_no_contact
            0 -> R.string.accuracy_unreliable
            1 -> R.string.accuracy_low
            2 -> R.string.accuracy_medium
            3 -> R.string.accuracy_high
            else -> R.string.accuracy_unknown
        },
    )

    private fun dp(v: Int) = (v * activity.resources.displayMetrics.density).toInt()

    companion object {
        fun kindName(kind: SensorKind): Int = when (kind) {
            SensorKind.ACCELEROMETER -> R.string.kind_accelerometer
            SensorKind.GYROSCOPE -> R.string.kind_gyroscope
            SensorKind.MAGNETOMETER -> R.string.kind_magnetometer
            SensorKind.ROTATION_VECTOR -> R.string.kind_rotation_vector
            SensorKind.GAME_ROTATION_VECTOR -> R.string.kind_game_rotation_vector
        }

        fun modeText(m: EffectiveMode): Int = when (m.reason) {
            ModeReason.NO_ACCELEROMETER -> R.string.mode_none
            ModeReason.NO_GYROSCOPE -> R.string.mode_acc_mag
            ModeReason.NO_GYROSCOPE_NO_MAGNETOMETER -> R.string.mode_tilt
            ModeReason.NO_MAGNETOMETER -> R.string.mode_imu_no_mag
            ModeReason.AS_CHOSEN -> if (m.mode == FusionMode.IMU) R.string.mode_imu_chosen else R.string.mode_marg
        }
    }
}
