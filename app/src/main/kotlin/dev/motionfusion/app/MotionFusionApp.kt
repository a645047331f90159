package dev.motionfusion.app

import android.app.Application
import com.google.android.material.color.DynamicColors

/** The application: Material You colours from the wallpaper on Android 12+ (the theme's own colours before). */
class MotionFusionApp : Application() {
    override fun onCreate() {
        super.onCreate()
        DynamicColors.applyToActivitiesIfAvailable(this)
    }
}
