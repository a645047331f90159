package dev.motionfusion.app.settings

import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.WorldFrame

/** How angles are shown. */
enum class AngleConvention {
    /**
     * Android's getOrientation: azimuth (0..360°, from magnetic north towards east, of the
     * screen's up direction), pitch (−90..90°, positive when the top edge tilts down), roll
     * (−180..180°, positive when the right edge tilts down: roll = atan2(−A_x, A_z) with A the
     * up direction in screen coordinates).
     */
    ANDROID,

    /**
     * Aerospace yaw, pitch, roll (intrinsic Z-Y-X) of the phone as a vehicle whose nose is the
     * screen's top edge, right wing the right edge, in North-East-Down: yaw 0..360° like azimuth,
     * pitch −90..90° positive nose up, roll −180..180° positive right edge down.
     */
    AEROSPACE,
}

/**
 * Everything the settings decide, validated: the whole [FilterSettings] (its own type checks
 * every value; the output frame stays ENU, the frame the app shows and records), the angle
 * convention, the requested sensor rate and when a recording stops by itself. One object for the live filter, the recorder (its
 * meta.json) and the settings screen; [dev.motionfusion.app.settings.Setting] lists its values.
 */
data class LiveSettings(
    val filter: FilterSettings = DEFAULT_FILTER,
    val convention: AngleConvention = AngleConvention.ANDROID,
    val rate: SamplingRate = SamplingRate.Hz(100),
    val limits: RecordingLimits = RecordingLimits(),
) {
    init {
        require(filter.outputFrame == WorldFrame.ENU) { "the app's filter outputs device → ENU, got ${filter.outputFrame}" }
    }

    /** 6D or 9D, as requested (the capture falls back to 6D without magnetometer). */
    val mode: FilterMode get() = filter.mode

    companion object {
        val DEFAULT_FILTER = FilterSettings()
    }
}
